// manyworlds render --env ID --out FILE: one frame (.png) or one episode
// (.mp4) of a MuJoCo env, rendered offscreen (OSMesa) and encoded by ffmpeg.
//
// Seeding follows `rollout` (SeedEpisode for episode 0, then one
// ResetTaskState): on a single task the recorded episode is the first
// episode `rollout` runs with the same arguments.
#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "apps/manyworlds/stop_signals.h"
#include "manyworlds/core/error.h"
#include "manyworlds/envs/all.h"
#ifdef MANYWORLDS_HAS_RENDER
#include "manyworlds/sim/render.h"
#include "manyworlds/sim/video.h"
#endif

namespace manyworlds::cli {
namespace {

struct RenderArgs {
  std::string env;
  std::string policy = "scripted";
  uint64_t seed = 0;
  uint64_t task_seed = 0;
  std::string camera;  // empty: the scene's default (MujocoScene::default_camera)
  int width = 640;
  int height = 480;
  int64_t steps = -1;  // -1: .png 0, .mp4 the whole episode
  int every = 2;
  double fps = 40;
  std::vector<std::string> options;
  std::string out;
};

#ifdef MANYWORLDS_HAS_RENDER

// " (task push, variation 7)" for a benchmark, "" otherwise.
std::string TaskLabel(const Env& env) {
  const nlohmann::json params = env.GetTaskState().params;
  if (!params.is_object() || !params.contains("task") || !params["task"].is_string()) return "";
  std::string label = " (task " + params["task"].get<std::string>();
  if (params.contains("variation") && params["variation"].is_number_integer()) {
    label += ", variation " + std::to_string(params["variation"].get<int64_t>());
  }
  return label + ")";
}

// Renders the env's current MuJoCo state and times the frames after the
// first (which includes setting up OpenGL for the model, ~0.3 s).
class FrameSource {
 public:
  FrameSource(const Env& env, std::string camera, const RenderArgs& args)
      : env_(env), camera_(std::move(camera)), renderer_(args.width, args.height) {}

  const std::vector<uint8_t>& Render() {
    const MujocoScene scene = ActiveMujocoScene(env_);
    const auto start = std::chrono::steady_clock::now();
    renderer_.Render(scene.model, scene.data, camera_, rgb_);
    if (rendered_++ > 0) {
      seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return rgb_;
  }
  // 0 until two frames were rendered
  double frames_per_s() const { return seconds_ > 0 ? (rendered_ - 1) / seconds_ : 0.0; }

 private:
  const Env& env_;
  std::string camera_;
  sim::Renderer renderer_;
  std::vector<uint8_t> rgb_ = std::vector<uint8_t>(
      static_cast<size_t>(renderer_.width()) * renderer_.height() * 3);
  double seconds_ = 0;
  int64_t rendered_ = 0;
};

void RunRender(const RenderArgs& args, CommandContext& context) {
  CheckPolicyName(args.policy);
  const sim::VideoFormat format = sim::VideoFormatForPath(args.out);
  const bool video = format == sim::VideoFormat::kMp4;
  if (video && (args.width % 2 != 0 || args.height % 2 != 0)) {
    throw ConfigError("an .mp4 (H.264, yuv420p) needs an even --width and --height, got " +
                      std::to_string(args.width) + "x" + std::to_string(args.height));
  }

  auto env = Make(args.env, ParseEnvOptions(args.options));
  CheckMujocoEnv(*env, "rendering");  // before the policy: its error would hide this one
  auto policy = SeedEpisode(*env, args.policy, args.seed, args.task_seed, /*episode=*/0);
  env->ResetTaskState();
  const std::string camera =
      args.camera.empty() ? std::string(ActiveMujocoScene(*env).default_camera) : args.camera;

  // steps to run: the whole episode (bounded like Rollout) unless given
  constexpr int64_t kUnlimitedCap = 100000;
  const int64_t limit = env->spec().max_episode_steps > 0 ? env->spec().max_episode_steps
                                                          : kUnlimitedCap;
  if (args.steps > limit) {  // it used to render the episode's last frame without a word
    throw ConfigError("render: --steps " + std::to_string(args.steps) +
                      " is past the end of the episode of '" + args.env + "' (" +
                      std::to_string(limit) + " steps); allowed: 0 to " + std::to_string(limit));
  }
  const int64_t steps = args.steps >= 0 ? args.steps : (video ? limit : 0);

  // a signal stops the loop; the writer's destructor removes the temporary file
  const StopSignals signals;
  FrameSource frames(*env, camera, args);
  Observation obs = env->Reset();
  policy->BeginEpisode();
  // the first frame checks the camera and the GL setup before ffmpeg starts
  const std::vector<uint8_t>& first = frames.Render();
  sim::VideoWriter writer(args.out, args.width, args.height, args.fps);
  if (video) writer.AddFrame(first);

  const int success_field = env->spec().InfoIndex("success");
  std::vector<float> action(env->spec().action_space.flat_size());
  double episode_return = 0;
  bool success = false, ended = false;
  int64_t t = 0;
  {
    std::optional<ProgressBar> progress;
    if (video) progress.emplace("render", steps, "steps", context.progress);
    while (t < steps && !ended && !StopSignals::received()) {
      policy->Act(obs.env_obs, obs.task_obs, action);
      StepResult r = env->Step(action);
      ++t;
      episode_return += r.reward;
      if (success_field >= 0 && r.info.values[success_field] > 0) success = true;
      ended = r.terminated || r.truncated;
      obs = std::move(r.obs);
      // every k-th step, and always the last one
      if (video && (t % args.every == 0 || ended || t == steps)) writer.AddFrame(frames.Render());
      if (progress) progress->Advance();
    }
  }
  if (StopSignals::received()) {
    std::cerr << "render: interrupted; " << args.out << " was not written\n";
    context.exit_code = StopSignals::exit_code();
    return;
  }
  if (!video) writer.AddFrame(t == 0 ? first : frames.Render());
  writer.Finish();

  std::cout << args.out << "\n";
  std::cout << args.env << TaskLabel(*env) << ": " << writer.frames()
            << (writer.frames() == 1 ? " frame " : " frames ") << args.width << "x"
            << args.height << " from camera " << camera << " after " << t << " steps"
            << (video ? " at " + Fixed(args.fps, args.fps == std::floor(args.fps) ? 0 : 2) + " fps"
                   : std::string()) << ", policy "
            << args.policy << ", return " << Fixed(episode_return, 2) << ", success "
            << (success_field < 0 ? "-" : success ? "yes" : "no");
  if (frames.frames_per_s() > 0) {
    std::cout << ", rendering " << Fixed(frames.frames_per_s(), 1) << " frames/s";
  }
  std::cout << "\n";
}

#else  // !MANYWORLDS_HAS_RENDER

void RunRender(const RenderArgs&, CommandContext&) {
  throw Error(
      "this build cannot render: it was configured without MuJoCo or without OSMesa "
      "(Debian: apt-get install libmujoco-dev libosmesa6-dev, then run cmake again)");
}

#endif  // MANYWORLDS_HAS_RENDER

}  // namespace

void AddRenderCommand(CLI::App& app, CommandContext& context) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render a MuJoCo env offscreen: one frame (.png) or one episode (.mp4)");
  cmd->footer(
      "The Sawyer tasks run 80 env steps per simulated second: the defaults (--every 2, --fps "
      "40) play an episode (500 steps, 251 frames) in real time, 6.25 s. Images are rendered "
      "with OSMesa (software OpenGL) and encoded by the ffmpeg program.");
  cmd->add_option("--env", args->env,
                  "env id: a MuJoCo env (a manipulation task or benchmark, "
                  "box-world-simple/-complex, half-cheetah-vel/-dir, "
                  "dmc-finger-spin/-cheetah-run/-walker-walk, the hipbmdp-* variants of those)")
      ->required();
  cmd->add_option("--policy", args->policy,
                  "policy: scripted (the manipulation tasks and benchmarks, box-world-*), or "
                  "random (any env, e.g. half-cheetah-*, dmc-*, hipbmdp-*)")
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "env seed (dynamics, initial states; policy seed)")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_option("--task-seed", args->task_seed,
                  "task seed (which task, and for a benchmark which variation, is drawn)")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_option("--camera", args->camera,
                  "camera: front, top, side, gripper, or a camera named in the model (the "
                  "box world's: top, perspective; the half-cheetah's: track; the dmc-*/hipbmdp-* "
                  "finger's: fixed, cheetah's and walker's: side). Default: track for the "
                  "half-cheetah, fixed for the finger, side for the dmc cheetah and walker, front "
                  "for the others");
  cmd->add_option("--width", args->width, "image width in pixels (even for .mp4)")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--height", args->height, "image height in pixels (even for .mp4)")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--steps", args->steps,
                  "env steps to run: .png renders the frame after them (default 0: the frame "
                  "after reset); .mp4 records them (default: the whole episode)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--every", args->every,
                  ".mp4: record every k-th step (and the first and last frame)")
      ->capture_default_str()
      ->check(AtLeastOne());
  cmd->add_option("--fps", args->fps, ".mp4: playback frames per second")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 1000.0));
  cmd->add_option("--option", args->options, "env option key=value (repeatable)");
  cmd->add_option("--out", args->out,
                  "output file: .png (one frame) or .mp4 (H.264); written atomically")
      ->required();
  cmd->callback([args, &context] { RunRender(*args, context); });
}

}  // namespace manyworlds::cli
