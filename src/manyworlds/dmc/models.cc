#include "manyworlds/dmc/models.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <numbers>

#include "manyworlds/sim/model.h"

namespace manyworlds::dmc {
namespace {

// A number as MJCF text, exact enough that the compiled model does not see the rounding.
std::string N(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.12g", x);
  return buffer;
}

// Degrees (as the published facts give them) written as radians.
std::string Deg(double degrees) { return N(degrees * std::numbers::pi / 180.0); }
std::string Range(double low_degrees, double high_degrees) {
  return Deg(low_degrees) + " " + Deg(high_degrees);
}

// What the three models share: the headlight and near clip plane of dm_control's scenes.
constexpr char kVisual[] = R"(  <visual>
    <headlight ambient="0.4 0.4 0.4" diffuse="0.8 0.8 0.8" specular="0.1 0.1 0.1"/>
    <map znear="0.01"/>
    <quality shadowsize="2048"/>
  </visual>
)";

}  // namespace

// The MJCF is laid out as MJCF, not as C++: clang-format would break it at every `+`.
// clang-format off
std::string FingerXml(const FingerParams& params) {
  const std::string finger_range = Range(-110, 110);
  const std::string touch_size = N(params.touch_site_x) + " 0.03 0.025";
  // The spinner hinge's damping is 0.03: dm_control's spin task sets it at every reset
  // (its file says 0.5, which no episode ever sees).
  return std::string(R"(<mujoco model="manyworlds_dmc_finger">
  <compiler angle="radian"/>
  <option timestep="0.01" cone="elliptic" iterations="200">
    <flag gravity="disable"/>
  </option>
)") + kVisual + R"(  <default>
    <geom solref="0.02 1" solimp="0 0.9 0.01" rgba="0.7 0.5 0.3 1"/>
    <joint type="hinge" axis="0 -1 0"/>
    <motor ctrllimited="true" ctrlrange="-1 1"/>
    <default class="phalanx">
      <joint limited="true" damping="2.5" range=")" + finger_range + R"("/>
      <site type="ellipsoid" size=")" + touch_size + R"(" group="3" rgba="0.5 0.5 0.5 0.3"/>
    </default>
  </default>
  <worldbody>
    <camera name="fixed" pos="0 -1 0.8" zaxis="0 -2 1"/>
    <light directional="true" pos="0 0 2" dir="0 0 -1" diffuse="0.6 0.6 0.6"
           specular="0.3 0.3 0.3"/>
    <geom name="ground" type="plane" size="0.6 0.2 10" rgba="0.2 0.3 0.4 1"/>
    <body name="proximal" pos="-0.2 0 0.4" childclass="phalanx">
      <joint name="proximal" ref=")" + Deg(-90) + R"("/>
      <geom name="proximal_axle" type="cylinder" size="0.034 0.033" zaxis="0 1 0"
            rgba="0.3 0.5 0.7 1"/>
      <geom name="proximal" type="capsule" size="0.03" fromto="0 0 0 0 0 -0.17"/>
      <body name="distal" pos="0 0 -0.18">
        <joint name="distal"/>
        <geom name="distal" type="capsule" size="0.028" fromto="0 0 0 0 0 -0.16"
              contype="0" conaffinity="0"/>
        <geom name="fingertip" type="capsule" size="0.03" fromto="0 0 -0.13 0 0 -0.161"
              rgba="0.7 0.4 0.2 1"/>
        <site name="touchtop" pos="0.01 0 -0.17"/>
        <site name="touchbottom" pos="-0.01 0 -0.17"/>
      </body>
    </body>
    <body name="spinner" pos="0.2 0 0.4">
      <joint name="hinge" damping="0.03" frictionloss="0.1"/>
      <geom name="cap1" type="capsule" size="0.04 0.09" pos="0.02 0 0"/>
      <geom name="cap2" type="capsule" size="0.04 0.09" pos="-0.02 0 0"/>
      <site name="tip" type="sphere" size="0.02" pos="0 0 0.13" rgba="1 0 0 0"/>
      <geom name="spinner_axle" type="cylinder" size="0.02 0.045" zaxis="0 1 0"
            rgba="0.3 0.5 0.7 1"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="proximal" joint="proximal" gear="30"/>
    <motor name="distal" joint="distal" gear="15"/>
  </actuator>
  <sensor>
    <jointpos name="proximal" joint="proximal"/>
    <jointpos name="distal" joint="distal"/>
    <jointvel name="proximal_velocity" joint="proximal"/>
    <jointvel name="distal_velocity" joint="distal"/>
    <jointvel name="hinge_velocity" joint="hinge"/>
    <framepos name="tip" objtype="site" objname="tip"/>
    <framepos name="spinner" objtype="xbody" objname="spinner"/>
    <touch name="touchtop" site="touchtop"/>
    <touch name="touchbottom" site="touchbottom"/>
  </sensor>
</mujoco>
)";
}

namespace {

// One cheetah limb segment: a body with its hinge (about y) and its capsule.
struct CheetahSegment {
  const char* name;  // of the body, its joint, its capsule and its motor
  const char* pos;   // the body in its parent's frame
  double low, high;  // joint range (degrees)
  const char* stiffness;
  const char* damping;
  const char* capsule_pos;  // the capsule's centre in the body frame
  double pitch;             // the capsule's rotation about y (degrees)
  const char* half_length;
};

// Thigh, shin and foot, each the parent of the next. The front thigh's upper limit is
// 0.4 degrees, as dm_control's file has it.
constexpr CheetahSegment kBackLeg[] = {
    {"bthigh", "-0.5 0 0", -30, 60, "240", "6", "0.1 0 -0.13", -218, "0.145"},
    {"bshin", "0.16 0 -0.25", -50, 50, "180", "4.5", "-0.14 0 -0.07", -116, "0.15"},
    {"bfoot", "-0.28 0 -0.14", -230, 50, "120", "3", "0.03 0 -0.097", -15, "0.094"}};
constexpr CheetahSegment kFrontLeg[] = {
    {"fthigh", "0.5 0 0", -57, 0.4, "180", "4.5", "-0.07 0 -0.12", 30, "0.133"},
    {"fshin", "-0.14 0 -0.24", -70, 50, "120", "3", "0.065 0 -0.09", -34, "0.106"},
    {"ffoot", "0.13 0 -0.18", -28, 28, "60", "1.5", "0.045 0 -0.07", -34, "0.07"}};

std::string CheetahLeg(const CheetahSegment (&leg)[3]) {
  std::string xml;
  for (int i = 0; i < 3; ++i) {
    const std::string indent(6 + 2 * i, ' ');
    const CheetahSegment& s = leg[i];
    const std::string name = std::string("name=\"") + s.name + "\"";
    xml += indent + "<body " + name + " pos=\"" + s.pos + "\">\n";
    xml += indent + "  <joint " + name + " range=\"" + Range(s.low, s.high) + "\" stiffness=\"" +
           s.stiffness + "\" damping=\"" + s.damping + "\"/>\n";
    xml += indent + "  <geom " + name + " pos=\"" + s.capsule_pos + "\" axisangle=\"0 1 0 " +
           Deg(s.pitch) + "\" size=\"0.046 " + s.half_length + "\"/>\n";
  }
  for (int i = 2; i >= 0; --i) xml += std::string(6 + 2 * i, ' ') + "</body>\n";
  return xml;
}

}  // namespace

std::string CheetahXml(const CheetahParams& params) {
  const std::string l = N(params.torso_half_length);
  // The floor has no class: MuJoCo's default friction 1, which wins over the limbs' 0.4.
  return std::string(R"(<mujoco model="manyworlds_dmc_cheetah">
  <compiler angle="radian" settotalmass="14"/>
  <option timestep="0.01"/>
  <statistic center="0 0 0.7" extent="2"/>
)") + kVisual + R"(  <default>
    <motor ctrllimited="true" ctrlrange="-1 1"/>
    <default class="limb">
      <joint type="hinge" axis="0 1 0" limited="true" damping="0.01" armature="0.1"
             stiffness="8"/>
      <geom type="capsule" size="0.046" contype="1" conaffinity="1" condim="3"
            friction="0.4 0.1 0.1" rgba="0.7 0.5 0.3 1"/>
    </default>
    <default class="root">
      <joint limited="false" damping="0" armature="0" stiffness="0"/>
    </default>
  </default>
  <worldbody>
    <geom name="ground" type="plane" conaffinity="1" pos="98 0 0" size="100 0.8 0.5"
          rgba="0.2 0.3 0.4 1"/>
    <body name="torso" pos="0 0 0.7" childclass="limb">
      <camera name="side" pos="0 -3 0" xyaxes="1 0 0 0 0 1" mode="trackcom"/>
      <light pos="0 0 2" dir="0 0 -1" mode="trackcom"/>
      <joint name="rootx" class="root" type="slide" axis="1 0 0"/>
      <joint name="rootz" class="root" type="slide" axis="0 0 1"/>
      <joint name="rooty" class="root" type="hinge" axis="0 1 0"/>
      <geom name="torso" fromto="-)" + l + " 0 0 " + l + R"( 0 0"/>
      <geom name="head" pos="0.6 0 0.1" axisangle="0 1 0 )" + Deg(50) + R"(" size="0.046 0.15"/>
)" + CheetahLeg(kBackLeg) + CheetahLeg(kFrontLeg) + R"(    </body>
  </worldbody>
  <actuator>
    <motor name="bthigh" joint="bthigh" gear="120"/>
    <motor name="bshin" joint="bshin" gear="90"/>
    <motor name="bfoot" joint="bfoot" gear="60"/>
    <motor name="fthigh" joint="fthigh" gear="90"/>
    <motor name="fshin" joint="fshin" gear="60"/>
    <motor name="ffoot" joint="ffoot" gear="30"/>
  </actuator>
  <sensor>
    <subtreelinvel name="torso_subtreelinvel" body="torso"/>
  </sensor>
</mujoco>
)";
}

namespace {

// One walker leg: thigh, leg (shin) and foot under the torso; `side` is "right" or "left",
// `y` the hip's lateral offset.
std::string WalkerLeg(const std::string& side, const char* y, double foot_half_length) {
  const std::string hip = Range(-20, 100), knee = Range(-150, 0), ankle = Range(-45, 45);
  return "      <body name=\"" + side + "_thigh\" pos=\"0 " + y + " -0.3\">\n" +
         "        <joint name=\"" + side + "_hip\" range=\"" + hip + "\"/>\n" +
         "        <geom name=\"" + side + "_thigh\" pos=\"0 0 -0.225\" size=\"0.05 0.225\"/>\n" +
         "        <body name=\"" + side + "_leg\" pos=\"0 0 -0.7\">\n" +
         "          <joint name=\"" + side + "_knee\" pos=\"0 0 0.25\" range=\"" + knee +
         "\"/>\n" +
         "          <geom name=\"" + side + "_leg\" size=\"0.04 0.25\"/>\n" +
         "          <body name=\"" + side + "_foot\" pos=\"0.06 0 -0.25\">\n" +
         "            <joint name=\"" + side + "_ankle\" pos=\"-0.06 0 0\" range=\"" + ankle +
         "\"/>\n" +
         "            <geom name=\"" + side + "_foot\" zaxis=\"1 0 0\" size=\"0.05 " +
         N(foot_half_length) + "\"/>\n" +
         "          </body>\n        </body>\n      </body>\n";
}

}  // namespace

std::string WalkerXml(const WalkerParams& params) {
  // Bodies collide only with the floor: their geoms have conaffinity 0, the floor 1.
  return std::string(R"(<mujoco model="manyworlds_dmc_walker">
  <compiler angle="radian"/>
  <option timestep="0.0025"/>
  <statistic center="0 0 1" extent="2"/>
)") + kVisual + R"(  <default>
    <joint limited="true" damping="0.1" armature="0.01" solimplimit="0 0.99 0.01"/>
    <geom contype="1" conaffinity="0" friction=")" + N(params.friction) + R"( 0.1 0.1"/>
    <motor ctrllimited="true" ctrlrange="-1 1"/>
    <default class="limb">
      <joint axis="0 -1 0"/>
      <geom type="capsule" rgba="0.7 0.5 0.3 1"/>
    </default>
  </default>
  <worldbody>
    <geom name="floor" type="plane" conaffinity="1" pos="248 0 0" size="250 0.8 0.2"
          rgba="0.2 0.3 0.4 1"/>
    <body name="torso" pos="0 0 1.3" childclass="limb">
      <camera name="side" pos="0 -2 0.7" zaxis="0 -0.866025403784 0.5" mode="trackcom"/>
      <light pos="0 0 2" dir="0 0 -1" mode="trackcom"/>
      <joint name="rootz" type="slide" axis="0 0 1" limited="false" armature="0" damping="0"/>
      <joint name="rootx" type="slide" axis="1 0 0" limited="false" armature="0" damping="0"/>
      <joint name="rooty" type="hinge" axis="0 1 0" limited="false" armature="0" damping="0"/>
      <geom name="torso" size="0.07 0.3"/>
)" + WalkerLeg("right", "-0.05", 0.1) +
         WalkerLeg("left", "0.05", params.left_foot_half_length) + R"(    </body>
  </worldbody>
  <actuator>
    <motor name="right_hip" joint="right_hip" gear="100"/>
    <motor name="right_knee" joint="right_knee" gear="50"/>
    <motor name="right_ankle" joint="right_ankle" gear="20"/>
    <motor name="left_hip" joint="left_hip" gear="100"/>
    <motor name="left_knee" joint="left_knee" gear="50"/>
    <motor name="left_ankle" joint="left_ankle" gear="20"/>
  </actuator>
  <sensor>
    <subtreelinvel name="torso_subtreelinvel" body="torso"/>
  </sensor>
</mujoco>
)";
}

// clang-format on

const CompiledMjcf& CompiledModel(const std::string& xml, std::string_view name) {
  static std::mutex mutex;
  static std::map<std::string, CompiledMjcf> cache;  // never erased: references stay valid
  const std::lock_guard<std::mutex> lock(mutex);
  if (const auto it = cache.find(xml); it != cache.end()) return it->second;
  sim::ModelPtr model = sim::LoadModelFromString(xml, {}, name);
  CompiledMjcf entry{xml, std::shared_ptr<const mjModel>(model.release(), sim::ModelDeleter())};
  return cache.emplace(xml, std::move(entry)).first->second;
}

}  // namespace manyworlds::dmc
