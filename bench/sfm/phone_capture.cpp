// hos-phone-capture-bench: one synthetic capture given to hos-pipeline
// twice, as plain upright JPEGs and as a phone gives them (in a subfolder,
// every other photo stored sideways with an EXIF rotation, two as HEIC), both
// with EXIF focal length and GPS and one photo rendered at twice the size
// (--no-large-photo: none), and the PSNR of both models re-rendered from
// held-out views. Prints a markdown table.
#include <CLI/CLI.hpp>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/colmap_io.h"
#include "core/error.h"
#include "core/sparse_model.h"
#include "core/subprocess.h"
#include "synth/geo_tags.h"
#include "tests/sfm/jpeg_fixtures.h"

namespace hos {
namespace {
namespace fs = std::filesystem;
using sfm::testing::PhoneExif;
using sfm::testing::write_bytes;

struct BenchOptions {
  fs::path output;
  fs::path bin;  // folder of the hos executables
  int views = 24;
  int width = 640;
  int height = 480;
  bool large_photo = true;  // one photo rendered at twice the size
};

// Runs a hos executable; its output goes to log. Throws on failure.
void run_hos(const BenchOptions& o, const std::string& program, std::vector<std::string> args, const fs::path& log) {
  args.insert(args.begin(), (o.bin / program).string());
  std::ofstream out(log);
  ProcessOptions process;
  process.argv = args;
  process.on_line = [&](std::string_view line) { out << line << "\n"; };
  const ProcessResult result = run_process(process);
  if (result.exit_code != 0) {
    throw StageError(program, "exit " + std::to_string(result.exit_code) + "; see " + log.string());
  }
}

// The EXIF a phone writes for a view: the true focal length (as COLMAP reads
// it: f = f35 / 35 * longest side) and the view's position on Earth.
PhoneExif phone_exif(const BenchOptions& o, const Camera& camera, const ImageRecord& view) {
  PhoneExif exif;
  exif.model = "hos phone";
  exif.focal_35mm = static_cast<int>(std::lround(camera.focal_x() / std::max(o.width, o.height) * 35.0));
  const GeoPosition origin{46.5, 6.6, 400.0};
  const GeoPosition gps = synth::scene_gps_position(view.center(), origin, 1.0);
  exif.latitude_deg = gps.latitude_deg;
  exif.longitude_deg = gps.longitude_deg;
  exif.altitude_m = gps.altitude_m;
  return exif;
}

cv::Mat read_photo(const fs::path& folder, const std::string& name) {
  cv::Mat photo = cv::imread((folder / name).string(), cv::IMREAD_COLOR);
  if (photo.empty()) throw InputError((folder / name).string(), "cannot read");
  return photo;
}

// Writes the plain and the phone copy of every view; returns the phone
// photos' staged names (what hos-sfm calls them) by the view's name. With
// large_photo, view 3 is rendered at twice the size (another camera's
// photo) in both copies: the plain copy holds the same photos, upright.
std::map<std::string, std::string> write_captures(const BenchOptions& o, const SparseModel& truth) {
  const fs::path images = o.output / "scene" / "images";
  std::map<std::string, std::string> view_of_staged;
  int index = 0;
  for (const auto& [id, view] : truth.images) {
    const bool large_photo = index == 3 && o.large_photo;
    const cv::Mat photo = read_photo(large_photo ? o.output / "scene-large" / "images" : images, view.name);
    PhoneExif exif = phone_exif(o, truth.camera_of(view), view);
    write_bytes(o.output / "plain" / view.name, sfm::testing::jpeg_with_phone_exif(photo, exif));
    cv::Mat sideways;
    cv::rotate(photo, sideways, cv::ROTATE_90_COUNTERCLOCKWISE);  // shown turned clockwise: EXIF orientation 6
    const std::string stem = "DCIM/100APPLE/IMG_" + std::to_string(1000 + index);
    std::string staged;
    if (index == 1 || index == 5) {
      exif.orientation = 6;
      const auto heic = sfm::testing::heic_with_exif(sideways, 6, exif);
      if (heic.empty()) throw StageError("phone-capture-bench", "libheif has no HEVC encoder here");
      write_bytes(o.output / "phone" / (stem + ".HEIC"), heic);
      staged = stem + ".HEIC.jpg";
    } else {
      exif.orientation = index % 2 == 0 ? 6 : 1;
      write_bytes(o.output / "phone" / (stem + ".JPG"),
                  sfm::testing::jpeg_with_phone_exif(exif.orientation == 6 ? sideways : photo, exif));
      staged = stem + ".JPG";
    }
    view_of_staged[staged] = view.name;
    ++index;
  }
  return view_of_staged;
}

// The run's SfM model with its photos under the views' names, so hos-eval
// can align it with the true cameras.
fs::path model_under_view_names(const fs::path& workspace,
                                const std::map<std::string, std::string>& view_of_staged,
                                const fs::path& folder) {
  SparseModel model = read_colmap_model(workspace / "sfm" / "undistorted" / "sparse");
  for (auto& [id, image] : model.images) {
    const auto it = view_of_staged.find(image.name);
    if (it != view_of_staged.end()) image.name = it->second;
  }
  fs::create_directories(folder);
  write_colmap_model(model, folder, ColmapFormat::kText);
  return folder;
}

struct RunFigures {
  int registered = 0;
  double psnr = 0.0;
  double ssim = 0.0;
  double coverage = 0.0;
};

// hos-pipeline on one copy, then hos-eval from the held-out views.
RunFigures run_and_measure(const BenchOptions& o,
                           const std::string& name,
                           const std::map<std::string, std::string>& view_of_staged) {
  const fs::path ws = o.output / ("ws-" + name), glb = o.output / (name + ".glb");
  run_hos(o, "hos-pipeline", {(o.output / name).string(), glb.string(), "--workspace", ws.string()},
          o.output / (name + "-pipeline.log"));
  const fs::path model = model_under_view_names(ws, view_of_staged, o.output / (name + "-model"));
  const fs::path scene = o.output / "scene", json = o.output / (name + "-eval.json");
  run_hos(o, "hos-eval",
          {"render", "--glb", glb.string(), "--model", (scene / "holdout" / "sparse").string(), "--images",
           (scene / "holdout" / "images").string(), "--align-model", model.string(), "--truth-model",
           (scene / "sparse").string(), "--json", json.string()},
          o.output / (name + "-eval.log"));
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);
  RunFigures f;
  f.registered = static_cast<int>(read_colmap_model(ws / "sfm" / "undistorted" / "sparse").images.size());
  f.psnr = j.at("mean_psnr").get<double>();
  f.ssim = j.at("mean_ssim").get<double>();
  double covered = 0.0;
  for (const auto& v : j.at("views")) covered += v.at("mask_pixels").get<double>();
  f.coverage = covered / (double(o.width) * o.height * std::max<std::size_t>(1, j.at("views").size()));
  return f;
}

void run_bench(const BenchOptions& o) {
  fs::create_directories(o.output);
  run_hos(o, "hos-synth",
          {"--output", (o.output / "scene").string(), "--views", std::to_string(o.views), "--holdout", "3", "--width",
           std::to_string(o.width), "--height", std::to_string(o.height), "--jpeg", "--progress", "none"},
          o.output / "synth.log");
  if (o.large_photo) {
    run_hos(o, "hos-synth",
            {"--output", (o.output / "scene-large").string(), "--views", std::to_string(o.views), "--width",
             std::to_string(2 * o.width), "--height", std::to_string(2 * o.height), "--jpeg", "--progress", "none"},
            o.output / "synth-large.log");
  }
  const SparseModel truth = read_colmap_model(o.output / "scene" / "sparse");
  const auto view_of_staged = write_captures(o, truth);
  const RunFigures plain = run_and_measure(o, "plain", {});
  const RunFigures phone = run_and_measure(o, "phone", view_of_staged);
  std::cout << "| photos | registered | held-out PSNR (dB) | SSIM | coverage |\n|---|---|---|---|---|\n";
  for (const auto& [name, f] : {std::pair{"plain", plain}, std::pair{"phone-like", phone}}) {
    std::cout << "| " << name << " | " << f.registered << " of " << o.views << " | " << f.psnr << " | " << f.ssim
              << " | " << f.coverage << " |\n";
  }
  std::cout << "phone-like minus plain: " << phone.psnr - plain.psnr << " dB\n";
}

}  // namespace
}  // namespace hos

int main(int argc, char** argv) {
  CLI::App app{"hos-phone-capture-bench: a synthetic capture as plain photos and as a phone gives them"};
  hos::BenchOptions o;
  app.add_option("--output", o.output, "work folder")->required();
  app.add_option("--views", o.views, "views of the capture")->check(CLI::Range(8, 200));
  app.add_option("--width", o.width, "view width in pixels")->check(CLI::Range(64, 8192));
  app.add_option("--height", o.height, "view height in pixels")->check(CLI::Range(64, 8192));
  bool no_large_photo = false;
  app.add_flag("--no-large-photo", no_large_photo, "every photo at the capture's size");
  CLI11_PARSE(app, argc, argv);
  o.large_photo = !no_large_photo;
  o.bin = std::filesystem::canonical("/proc/self/exe").parent_path();
  try {
    hos::run_bench(o);
  } catch (const std::exception& e) {
    std::cerr << "hos-phone-capture-bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
