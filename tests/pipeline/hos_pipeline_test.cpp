// hos-pipeline end to end: a small hos-synth scene through every stage into
// a .glb, checked with the glTF validator and against the true mesh, then
// the resume and interruption behaviour, and bad invocations. Parts whose
// executables are not built are skipped with a message.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "core/exit_codes.h"
#include "core/reporter.h"
#include "core/subprocess.h"
#include "pipeline/file_hash.h"
#include "pipeline/run_record.h"
#include "pipeline/stage_paths.h"
#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;
using hos::testing::read_text;
using hos::testing::shell_quote;
using ::testing::HasSubstr;

fs::path exe(const std::string& name) { return hos::testing::executable(name); }

// Stages that ran, from the driver's "running <stage>" lines.
std::vector<std::string> stages_run(const std::string& output) {
  std::vector<std::string> out;
  static const std::regex kRunning(R"(\[pipeline\] running (\w+))");
  for (auto it = std::sregex_iterator(output.begin(), output.end(), kRunning); it != std::sregex_iterator(); ++it) {
    out.push_back((*it)[1]);
  }
  return out;
}

// Runs the glTF validator (npm package gltf-validator, installed into the
// build folder on first use). Returns the number of errors, or -1 if the
// validator is not available (no node/npm or no network).
int gltf_validator_errors(const fs::path& glb, std::string& report) {
  if (find_executable("node").empty() || find_executable("npm").empty()) return -1;
  const fs::path prefix = hos::testing::bin_dir().parent_path() / "npm";
  const fs::path module = prefix / "node_modules" / "gltf-validator";
  if (!fs::exists(module)) {
    hos::testing::run_command(
        "npm install --prefix " + shell_quote(prefix.string()) + " gltf-validator --no-audit --no-fund",
        prefix.parent_path() / "npm-install.log");
    if (!fs::exists(module)) return -1;
  }
  const fs::path script = glb.parent_path() / "validate.js";
  std::ofstream(script) << R"(const fs = require('fs');
const validator = require(process.argv[2]);
validator.validateBytes(new Uint8Array(fs.readFileSync(process.argv[3])))
  .then((r) => { console.log(JSON.stringify(r.issues)); process.exit(0); })
  .catch((e) => { console.log(JSON.stringify({numErrors: 1, error: String(e)})); process.exit(0); });
)";
  const fs::path out = glb.parent_path() / "validator.json";
  hos::testing::run_command("node " + shell_quote(script.string()) + " " + shell_quote(module.string()) + " " +
                            shell_quote(glb.string()) + " > " + shell_quote(out.string()));
  report = read_text(out);
  try {
    return nlohmann::json::parse(report).value("numErrors", 1);
  } catch (const nlohmann::json::exception&) {
    return 1;
  }
}

// The first number stored under any of the keys, searched recursively.
std::optional<double> find_number(const nlohmann::json& j, const std::vector<std::string>& keys) {
  if (j.is_object()) {
    for (const auto& k : keys) {
      if (j.contains(k) && j[k].is_number()) return j[k].get<double>();
    }
  }
  if (j.is_structured()) {
    for (const auto& item : j) {
      if (auto v = find_number(item, keys)) return v;
    }
  }
  return std::nullopt;
}

// Content fingerprints of what mvs and the later stages wrote, and of the
// result, by name: equal maps mean byte-identical outputs.
std::map<std::string, std::string> outputs_after_mvs(const fs::path& workspace, const fs::path& result) {
  const StagePaths paths(workspace);
  std::map<std::string, std::string> out;
  for (const fs::path& file : {paths.points, paths.mesh, paths.refined_mesh, paths.textured_model, result}) {
    Fingerprint fingerprint;
    fingerprint.add_file_contents(file);
    out[file.filename().string()] = fingerprint.hex();
  }
  return out;
}

class HosPipelineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(exe("hos-pipeline"))) GTEST_SKIP() << "hos-pipeline is not built";
  }
  int pipeline(const std::string& args, const std::string& log_name) {
    return hos::testing::run_command(shell_quote(exe("hos-pipeline").string()) + " --progress plain " + args,
                                     dir_ / log_name);
  }
  std::string log(const std::string& log_name) const { return read_text(dir_ / log_name); }

  hos::testing::TempDir dir_;
};

TEST_F(HosPipelineTest, MissingPhotoFolderIsBadInput) {
  EXPECT_EQ(pipeline(shell_quote((dir_ / "nope").string()) + " " + shell_quote((dir_ / "out.glb").string()), "o"),
            kExitBadInput);
  EXPECT_THAT(log("o"), HasSubstr("photo folder does not exist"));
  EXPECT_FALSE(fs::exists(dir_ / "out_workspace"));
}

TEST_F(HosPipelineTest, OutputInMissingFolderIsAnOutputError) {
  fs::create_directories(dir_ / "photos");
  EXPECT_EQ(
      pipeline(shell_quote((dir_ / "photos").string()) + " " + shell_quote((dir_ / "no" / "out.glb").string()), "o"),
      kExitOutputFailed);
  EXPECT_THAT(log("o"), HasSubstr("does not exist"));
  EXPECT_FALSE(fs::exists(dir_ / "no"));
}

TEST_F(HosPipelineTest, UnknownConfigKeyNamesFileLineAndClosestKey) {
  fs::create_directories(dir_ / "photos");
  std::ofstream(dir_ / "my.yaml") << "sfm:\n  matcher: auto\n  camera_mdel: PINHOLE\n";
  EXPECT_EQ(pipeline(shell_quote((dir_ / "photos").string()) + " " + shell_quote((dir_ / "out.glb").string()) +
                         " --config " + shell_quote((dir_ / "my.yaml").string()),
                     "o"),
            kExitUsage);
  EXPECT_THAT(log("o"), HasSubstr("sfm.camera_mdel"));
  EXPECT_THAT(log("o"), HasSubstr("my.yaml, line 3"));
  EXPECT_THAT(log("o"), HasSubstr("did you mean sfm.camera_model"));
}

TEST_F(HosPipelineTest, MissingPresetListsThePresets) {
  fs::create_directories(dir_ / "photos");
  EXPECT_EQ(pipeline(shell_quote((dir_ / "photos").string()) + " " + shell_quote((dir_ / "out.glb").string()) +
                         " --preset turbo",
                     "o"),
            kExitUsage);
  EXPECT_THAT(log("o"), HasSubstr("fast, default, quality"));
}

TEST_F(HosPipelineTest, PrintDefaultConfigIsTheCommittedFile) {
  ASSERT_EQ(hos::testing::run_command(shell_quote(exe("hos-pipeline").string()) + " --print-default-config",
                                      dir_ / "default.yaml"),
            0);
  EXPECT_THAT(log("default.yaml"), HasSubstr("sfm:\n  colmap: colmap"));
}

// A cancel source that fires once mvs has been running for a moment.
class StopDuringMvs : public Reporter {
 public:
  explicit StopDuringMvs(fs::path run_json) : run_json_(std::move(run_json)) {}
  bool cancel_requested() const override {
    if (fired_) return true;
    const RunRecord record = load_run_record(run_json_);
    const auto it = record.stages.find("mvs");
    if (it != record.stages.end() && it->second.state == "running") {
      if (!seen_) seen_ = std::chrono::steady_clock::now();
      fired_ = std::chrono::steady_clock::now() - *seen_ > std::chrono::seconds(2);
    }
    return fired_;
  }

 private:
  fs::path run_json_;
  mutable std::optional<std::chrono::steady_clock::time_point> seen_;
  mutable bool fired_ = false;
};

// Accuracy and completeness against the true surface the cameras saw,
// after aligning the recovered cameras to the true ones, and novel views.
void expect_accurate_model(const fs::path& dir, const fs::path& scene, const fs::path& ws, const fs::path& out) {
  if (fs::exists(exe("hos-eval"))) {
    const std::string align = " --align-model " + shell_quote((ws / "sfm" / "undistorted" / "sparse").string()) +
                              " --truth-model " + shell_quote((scene / "sparse").string());
    const fs::path eval_json = dir / "eval.json";
    ASSERT_EQ(hos::testing::run_command(shell_quote(exe("hos-eval").string()) + " mesh --result " +
                                            shell_quote(out.string()) + " --truth " +
                                            shell_quote((scene / "gt_mesh.ply").string()) + align + " --visible-in " +
                                            shell_quote((scene / "sparse").string()) +
                                            " --thresholds 0.01,0.02 --json " + shell_quote(eval_json.string()),
                                        dir / "eval.log"),
              0)
        << read_text(dir / "eval.log");
    const auto j = nlohmann::json::parse(read_text(eval_json));
    ASSERT_EQ(j["thresholds"].size(), 2u) << j.dump(2);
    const double f1 = j["thresholds"][0]["f_score"].get<double>(), f2 = j["thresholds"][1]["f_score"].get<double>();
    std::cout << "F-score at 1% / 2% of the diagonal: " << f1 << " / " << f2 << "\n";
    // Measured with the defaults (four sfm runs): F 0.924-0.930 at 1% and
    // 0.947-0.953 at 2% (docs/pipeline.md, "Accuracy of the defaults"). The
    // bounds leave about 0.025 for COLMAP's run-to-run variation (0.01-0.03
    // measured before); 0.9 at 1% is the issue's target.
    EXPECT_GE(f1, 0.90) << j.dump(2);
    EXPECT_GE(f2, 0.92) << j.dump(2);

    const fs::path render_json = dir / "render.json";
    ASSERT_EQ(
        hos::testing::run_command(shell_quote(exe("hos-eval").string()) + " render --glb " + shell_quote(out.string()) +
                                      " --model " + shell_quote((scene / "holdout" / "sparse").string()) +
                                      " --images " + shell_quote((scene / "holdout" / "images").string()) + align +
                                      " --json " + shell_quote(render_json.string()),
                                  dir / "render.log"),
        0)
        << read_text(dir / "render.log");
    const auto psnr = find_number(nlohmann::json::parse(read_text(render_json)), {"mean_psnr"});
    ASSERT_TRUE(psnr.has_value());
    std::cout << "held-out views PSNR: " << *psnr << " dB\n";
    EXPECT_GE(*psnr, 20.0);
  } else {
    std::cout << "hos-eval is not built; accuracy check skipped\n";
  }
}

// hos-pipeline from mvs on (with recon.lambda 0.25), stopped by SIGTERM
// once mvs has run for a moment; its output in output.
ProcessResult run_interrupted_during_mvs(const fs::path& scene,
                                         const fs::path& out,
                                         const fs::path& ws,
                                         std::string& output) {
  StopDuringMvs stopper(ws / "run.json");
  ProcessOptions interrupted;
  interrupted.argv = {exe("hos-pipeline").string(),
                      (scene / "images").string(),
                      out.string(),
                      "--preset",
                      "default",
                      "--set",
                      "recon.lambda=0.25",
                      "--force",
                      "--from",
                      "mvs",
                      "--progress",
                      "plain"};
  interrupted.on_line = [&](std::string_view line) { output += std::string(line) + "\n"; };
  interrupted.cancel_source = &stopper;
  return run_process(interrupted);
}

TEST_F(HosPipelineTest, SyntheticSceneEndToEndWithResume) {
  const std::string missing =
      hos::testing::missing_executables({"hos-synth", "hos-sfm", "hos-mvs", "hos-recon", "hos-refine", "hos-texture"});
  if (!missing.empty()) GTEST_SKIP() << "not built:" << missing;
  if (find_executable("colmap").empty()) GTEST_SKIP() << "colmap is not installed";
  const fs::path scene = dir_ / "scene";
  ASSERT_EQ(hos::testing::make_synth_scene(scene, 16, 2, dir_ / "synth.log"), 0) << log("synth.log");
  const fs::path out = dir_ / "out.glb";
  const fs::path ws = dir_ / "out_workspace";
  const std::string base =
      shell_quote((scene / "images").string()) + " " + shell_quote(out.string()) + " --preset default";

  // 1. The whole pipeline (the .glb's vertices stay in the cameras' frame, the
  // viewer's up axis is only in its root node, so the camera alignment applies).
  ASSERT_EQ(pipeline(base, "run1"), 0) << log("run1");
  EXPECT_THAT(stages_run(log("run1")), ::testing::ElementsAre("sfm", "mvs", "recon", "refine", "texture"));
  ASSERT_TRUE(fs::exists(out));
  EXPECT_THAT(log("run1"), HasSubstr("result: " + out.string()));

  // 2. The result is valid glTF.
  std::string report;
  const int errors = gltf_validator_errors(out, report);
  if (errors < 0) {
    std::cout << "glTF validator unavailable (node/npm or network); validation skipped\n";
  } else {
    EXPECT_EQ(errors, 0) << report;
  }

  // 3. Accuracy and completeness against the true surface the cameras saw,
  // after aligning the recovered cameras to the true ones, and novel views.
  // Measured at 16 views, 640x480, default preset (four runs): held-out
  // PSNR 24.5-25.5 dB; COLMAP's model differs from run to run (its
  // descriptor matching is not repeatable).
  expect_accurate_model(dir_.path(), scene, ws, out);

  // 4. Nothing changed: nothing runs.
  ASSERT_EQ(pipeline(base, "run2"), 0) << log("run2");
  EXPECT_TRUE(stages_run(log("run2")).empty()) << log("run2");

  // 5. Deleting the texture output re-runs only texture.
  fs::remove(ws / "texture" / "model.glb");
  ASSERT_EQ(pipeline(base, "run3"), 0) << log("run3");
  EXPECT_THAT(stages_run(log("run3")), ::testing::ElementsAre("texture"));

  // 6. A changed recon option re-runs recon, refine and texture only.
  ASSERT_EQ(pipeline(base + " --set recon.lambda=0.25", "run4"), 0) << log("run4");
  EXPECT_THAT(stages_run(log("run4")), ::testing::ElementsAre("recon", "refine", "texture"));
  const auto uninterrupted = outputs_after_mvs(ws, out);

  // 7. Interrupted during mvs (SIGTERM to the driver): exit 130 with the
  // resume hint; the same command then finishes without redoing sfm, and its
  // result is byte for byte the uninterrupted one of step 6 (the stages are
  // deterministic for a given input, config and thread count).
  const std::string sfm_finished = load_run_record(ws / "run.json").stages.at("sfm").finished_at;
  std::string interrupted_output;
  const ProcessResult stopped = run_interrupted_during_mvs(scene, out, ws, interrupted_output);
  EXPECT_EQ(stopped.exit_code, kExitInterrupted) << interrupted_output;
  EXPECT_THAT(interrupted_output, HasSubstr("Re-run the same command to resume"));
  EXPECT_EQ(load_run_record(ws / "run.json").stages.at("mvs").state, "interrupted");
  ASSERT_EQ(pipeline(base + " --set recon.lambda=0.25", "run5"), 0) << log("run5");
  EXPECT_THAT(stages_run(log("run5")), ::testing::ElementsAre("mvs", "recon", "refine", "texture"));
  EXPECT_EQ(load_run_record(ws / "run.json").stages.at("sfm").finished_at, sfm_finished);
  EXPECT_TRUE(fs::exists(out));
  EXPECT_EQ(outputs_after_mvs(ws, out), uninterrupted);
}

}  // namespace
}  // namespace hos::pipeline
