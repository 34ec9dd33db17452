#include "manyworlds/sim/mjcf.h"

#include <cmath>
#include <cstdio>

#include "manyworlds/core/error.h"

namespace manyworlds::sim {
namespace {

void AppendNumber(std::string* out, double value) {
  if (!std::isfinite(value)) {
    throw Error("MJCF: cannot write the non-finite number " + std::to_string(value));
  }
  char text[32];
  // %.17g round-trips every double; integers come out without a fraction
  std::snprintf(text, sizeof(text), "%.17g", value);
  *out += text;
}

void AppendEscaped(std::string* out, std::string_view text) {
  for (const char c : text) {
    switch (c) {
      case '&': *out += "&amp;"; break;
      case '<': *out += "&lt;"; break;
      case '>': *out += "&gt;"; break;
      case '"': *out += "&quot;"; break;
      default: *out += c;
    }
  }
}

std::string Numbers(std::span<const double> values) {
  std::string text;
  for (size_t i = 0; i < values.size(); ++i) {
    if (i > 0) text += ' ';
    AppendNumber(&text, values[i]);
  }
  return text;
}

void SetName(MjcfElement& e, std::string_view name) {
  if (!name.empty()) e.Set("name", name);
}

std::span<const double> Span(const Vec3& v) { return {v.data(), v.size()}; }

}  // namespace

const char* MjcfName(GeomType type) {
  switch (type) {
    case GeomType::kPlane: return "plane";
    case GeomType::kBox: return "box";
    case GeomType::kSphere: return "sphere";
    case GeomType::kCylinder: return "cylinder";
    case GeomType::kCapsule: return "capsule";
  }
  return "sphere";
}

const char* MjcfName(JointType type) {
  switch (type) {
    case JointType::kSlide: return "slide";
    case JointType::kHinge: return "hinge";
    case JointType::kFree: return "free";
  }
  return "hinge";
}

MjcfElement& MjcfElement::Set(std::string_view name, std::string_view value) {
  for (auto& [key, text] : attributes_) {
    if (key == name) {
      text = value;
      return *this;
    }
  }
  attributes_.emplace_back(std::string(name), std::string(value));
  return *this;
}

MjcfElement& MjcfElement::Set(std::string_view name, double value) {
  std::string text;
  AppendNumber(&text, value);
  return Set(name, std::string_view(text));
}

MjcfElement& MjcfElement::Set(std::string_view name, std::span<const double> values) {
  return Set(name, std::string_view(Numbers(values)));
}

std::optional<std::string> MjcfElement::Get(std::string_view name) const {
  for (const auto& [key, text] : attributes_) {
    if (key == name) return text;
  }
  return std::nullopt;
}

MjcfElement& MjcfElement::AddChild(std::string tag) {
  children_.push_back(std::make_unique<MjcfElement>(std::move(tag)));
  return *children_.back();
}

MjcfElement& MjcfElement::Child(std::string_view tag) {
  for (auto& child : children_) {
    if (child->tag() == tag) return *child;
  }
  return AddChild(std::string(tag));
}

void MjcfElement::Write(std::string* out, int depth) const {
  out->append(static_cast<size_t>(2 * depth), ' ');
  *out += '<';
  *out += tag_;
  for (const auto& [key, text] : attributes_) {
    *out += ' ';
    *out += key;
    *out += "=\"";
    AppendEscaped(out, text);
    *out += '"';
  }
  if (children_.empty()) {
    *out += "/>\n";
    return;
  }
  *out += ">\n";
  for (const auto& child : children_) child->Write(out, depth + 1);
  out->append(static_cast<size_t>(2 * depth), ' ');
  *out += "</";
  *out += tag_;
  *out += ">\n";
}

MjcfCamera MjcfCamera::LookAt(std::string name, const Vec3& pos, const Vec3& target,
                              double fovy) {
  // view direction f; image right = f x up, image up = right x f
  Vec3 f = {target[0] - pos[0], target[1] - pos[1], target[2] - pos[2]};
  const Vec3 up = {0, 0, 1};
  Vec3 right = {f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2],
                f[0] * up[1] - f[1] * up[0]};
  const double norm = std::sqrt(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
  if (!(norm > 1e-9)) {
    throw Error("MJCF camera '" + name +
                "': LookAt needs a view direction that is not vertical; set xyaxes instead");
  }
  for (double& r : right) r /= norm;
  Vec3 image_up = {right[1] * f[2] - right[2] * f[1], right[2] * f[0] - right[0] * f[2],
                   right[0] * f[1] - right[1] * f[0]};
  MjcfCamera camera;
  camera.name = std::move(name);
  camera.pos = pos;
  camera.xyaxes = {right[0], right[1], right[2], image_up[0], image_up[1], image_up[2]};
  camera.fovy = fovy;
  return camera;
}

MjcfBody MjcfBody::AddBody(std::string_view name, const Vec3& pos) {
  MjcfElement& body = element_->AddChild("body");
  SetName(body, name);
  body.Set("pos", Span(pos));
  return MjcfBody(body);
}

MjcfElement& MjcfBody::AddGeom(const MjcfGeom& g) {
  MjcfElement& e = element_->AddChild("geom");
  SetName(e, g.name);
  e.Set("type", MjcfName(g.type));
  if (!g.size.empty()) e.Set("size", std::span<const double>(g.size));
  e.Set("pos", Span(g.pos));
  if (g.quat) e.Set("quat", std::span<const double>(g.quat->data(), 4));
  if (g.rgba) e.Set("rgba", std::span<const double>(g.rgba->data(), 4));
  if (!g.material.empty()) e.Set("material", g.material);
  if (g.mass) e.Set("mass", *g.mass);
  if (g.friction) e.Set("friction", Span(*g.friction));
  if (g.contype) e.Set("contype", *g.contype);
  if (g.conaffinity) e.Set("conaffinity", *g.conaffinity);
  if (g.condim) e.Set("condim", *g.condim);
  if (g.group) e.Set("group", *g.group);
  return e;
}

MjcfElement& MjcfBody::AddJoint(const MjcfJoint& j) {
  MjcfElement& e = element_->AddChild("joint");
  SetName(e, j.name);
  e.Set("type", MjcfName(j.type));
  if (j.type != JointType::kFree) e.Set("axis", Span(j.axis));
  if (j.damping) e.Set("damping", *j.damping);
  if (j.armature) e.Set("armature", *j.armature);
  if (j.range) {
    e.Set("limited", "true");
    e.Set("range", std::span<const double>(j.range->data(), 2));
  } else if (j.type != JointType::kFree) {
    e.Set("limited", "false");
  }
  return e;
}

MjcfElement& MjcfBody::AddSite(const MjcfSite& s) {
  MjcfElement& e = element_->AddChild("site");
  SetName(e, s.name);
  e.Set("type", MjcfName(s.type));
  if (!s.size.empty()) e.Set("size", std::span<const double>(s.size));
  e.Set("pos", Span(s.pos));
  if (s.rgba) e.Set("rgba", std::span<const double>(s.rgba->data(), 4));
  if (s.group) e.Set("group", *s.group);
  return e;
}

MjcfElement& MjcfBody::AddCamera(const MjcfCamera& c) {
  MjcfElement& e = element_->AddChild("camera");
  SetName(e, c.name);
  e.Set("pos", Span(c.pos));
  e.Set("xyaxes", std::span<const double>(c.xyaxes.data(), 6));
  e.Set("fovy", c.fovy);
  return e;
}

MjcfElement& MjcfBody::AddLight(const MjcfLight& l) {
  MjcfElement& e = element_->AddChild("light");
  SetName(e, l.name);
  e.Set("pos", Span(l.pos));
  e.Set("dir", Span(l.dir));
  e.Set("diffuse", Span(l.diffuse));
  e.Set("specular", Span(l.specular));
  e.Set("directional", l.directional ? "true" : "false");
  e.Set("castshadow", l.castshadow ? "true" : "false");
  return e;
}

MjcfBuilder::MjcfBuilder(std::string model_name) : name_(std::move(model_name)) {
  if (name_.empty()) throw Error("MjcfBuilder: the model needs a name");
  root_.Set("model", name_);
  compiler().Set("angle", "radian");
}

MjcfElement& MjcfBuilder::AddTexture(const MjcfTexture& t) {
  MjcfElement& e = asset().AddChild("texture");
  SetName(e, t.name);
  e.Set("type", t.type);
  e.Set("builtin", t.builtin);
  e.Set("rgb1", Span(t.rgb1));
  e.Set("rgb2", Span(t.rgb2));
  e.Set("width", t.width);
  e.Set("height", t.height);
  if (!t.mark.empty()) e.Set("mark", t.mark);
  if (t.markrgb) e.Set("markrgb", Span(*t.markrgb));
  return e;
}

MjcfElement& MjcfBuilder::AddMaterial(const MjcfMaterial& m) {
  MjcfElement& e = asset().AddChild("material");
  SetName(e, m.name);
  if (!m.texture.empty()) e.Set("texture", m.texture);
  if (m.texrepeat) e.Set("texrepeat", std::span<const double>(m.texrepeat->data(), 2));
  if (m.texuniform) e.Set("texuniform", "true");
  if (m.rgba) e.Set("rgba", std::span<const double>(m.rgba->data(), 4));
  if (m.specular) e.Set("specular", *m.specular);
  if (m.shininess) e.Set("shininess", *m.shininess);
  if (m.reflectance) e.Set("reflectance", *m.reflectance);
  return e;
}

MjcfElement& MjcfBuilder::AddMotor(const MjcfMotor& m) {
  MjcfElement& e = actuator().AddChild("motor");
  SetName(e, m.name);
  e.Set("joint", m.joint);
  e.Set("gear", m.gear);
  e.Set("ctrllimited", "true");
  e.Set("ctrlrange", std::span<const double>(m.ctrlrange.data(), 2));
  return e;
}

std::string MjcfBuilder::ToXml() const {
  std::string xml;
  xml.reserve(4096);
  root_.Write(&xml, 0);
  return xml;
}

ModelPtr MjcfBuilder::Build() const {
  return LoadModelFromString(ToXml(), {}, name_ + ".xml");
}

}  // namespace manyworlds::sim
