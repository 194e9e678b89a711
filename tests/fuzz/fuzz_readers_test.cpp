// Seeded mutation fuzzing of every reader of a user's file: PLY (ASCII and
// binary, points and meshes), COLMAP models (binary and text), the YAML
// configuration, Stanford .conf range scans, and photo headers. A reader
// passes when every mutant gives a clean result or one of the documented
// errors (InputError: exit 3, ConfigError: exit 2), never another exception
// (exit 70), a crash or a hang (ctest's timeout). A failing mutant is kept
// in fuzz-failures/ of the build folder, named by reader, seed and iteration.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <opencv2/imgcodecs.hpp>
#include <typeinfo>

#include "core/colmap_io.h"
#include "core/error.h"
#include "core/ply_io.h"
#include "pipeline/pipeline_config.h"
#include "recon/scans.h"
#include "sfm/exif.h"
#include "sfm/image_inputs.h"
#include "tests/fuzz/mutator.h"
#include "tests/sfm/jpeg_fixtures.h"
#include "tests/support/sparse_model_fixture.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {
namespace fs = std::filesystem;
using testing::Mutator;
using testing::read_file;
using testing::write_file;

constexpr int kIterations = 300;  // per reader: a few seconds in all

// Runs read on one mutant; anything but a clean return or an allowed error
// is a failure that keeps the mutant.
void expect_documented_outcome(const std::string& reader,
                               std::uint64_t seed,
                               int iteration,
                               const std::string& mutant,
                               const std::function<void()>& read) {
  std::string problem;
  try {
    read();
  } catch (const InputError&) {
  } catch (const ConfigError&) {
  } catch (const std::exception& e) {
    problem = std::string(typeid(e).name()) + ": " + e.what();
  }
  if (problem.empty()) return;
  const fs::path keep =
      fs::path("fuzz-failures") / (reader + "-" + std::to_string(seed) + "-" + std::to_string(iteration));
  fs::create_directories(keep.parent_path());
  write_file(keep, mutant);
  ADD_FAILURE() << reader << " (seed " << seed << ", iteration " << iteration << ", kept as " << keep.string()
                << ") ended in an undocumented error (exit 70): " << problem;
}

// Mutants of `valid`, each written to `file` and read by `read`.
void fuzz_file(const std::string& reader,
               std::uint64_t salt,
               const std::string& valid,
               bool text,
               const fs::path& file,
               const std::function<void()>& read,
               int iterations = kIterations) {
  const std::uint64_t seed = testing::fuzz_seed() * 1000003 + salt;
  Mutator mutator(seed);
  const int n = testing::fuzz_iterations(iterations);
  for (int i = 0; i < n; ++i) {
    const std::string mutant = mutator.mutate(valid, text);
    write_file(file, mutant);
    expect_documented_outcome(reader, seed, i, mutant, read);
  }
}

PointCloud small_cloud() {
  PointCloud c;
  for (int i = 0; i < 40; ++i) {
    const float t = 0.3f * static_cast<float>(i);
    c.positions.emplace_back(std::cos(t), std::sin(t), 0.1f * t);
    c.normals.emplace_back(std::cos(t), std::sin(t), 0.0f);
    c.colors.push_back({static_cast<std::uint8_t>(i), 20, 200});
    c.confidence.push_back(0.5f + 0.01f * static_cast<float>(i));
  }
  return c;
}

TriangleMesh small_mesh() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

// The promises a successful point read makes.
void check_cloud(const PointCloud& c) {
  c.check_consistent();
  for (const auto& p : c.positions) ASSERT_TRUE(p.allFinite());
  for (float w : c.confidence) ASSERT_TRUE(w >= 0.0f && std::isfinite(w));
}

TEST(FuzzReaders, PlyPointClouds) {
  testing::TempDir dir;
  int salt = 0;
  for (const PlyFormat format : {PlyFormat::kAscii, PlyFormat::kBinaryLittleEndian, PlyFormat::kBinaryBigEndian}) {
    write_point_cloud_ply(dir / "valid.ply", small_cloud(), format);
    const fs::path file = dir / "mutant.ply";
    ++salt;
    fuzz_file("ply-points-" + std::to_string(salt), salt, read_file(dir / "valid.ply"), format == PlyFormat::kAscii,
              file, [&] { check_cloud(read_point_cloud_ply(file)); });
  }
}

TEST(FuzzReaders, PlyMeshes) {
  testing::TempDir dir;
  int salt = 10;
  for (const PlyFormat format : {PlyFormat::kAscii, PlyFormat::kBinaryLittleEndian}) {
    write_mesh_ply(dir / "valid.ply", small_mesh(), format);
    const fs::path file = dir / "mutant.ply";
    ++salt;
    fuzz_file("ply-mesh-" + std::to_string(salt), salt, read_file(dir / "valid.ply"), format == PlyFormat::kAscii, file,
              [&] { read_mesh_ply(file).check_consistent(); });
  }
}

void fuzz_colmap(ColmapFormat format, const std::string& ext, std::uint64_t salt) {
  testing::TempDir dir;
  write_colmap_model(hos::testing::small_sparse_model(), dir / "valid", format);
  const bool text = format == ColmapFormat::kText;
  // Each of the three files in turn, the others valid.
  for (const char* name : {"cameras", "images", "points3D"}) {
    fs::remove_all(dir / "model");
    fs::copy(dir / "valid", dir / "model");
    const fs::path file = dir / "model" / (std::string(name) + ext);
    fuzz_file(
        std::string("colmap-") + name + ext, salt++, read_file(dir / "valid" / (std::string(name) + ext)), text, file,
        [&] { text ? read_colmap_model_text(dir / "model") : read_colmap_model_binary(dir / "model"); },
        kIterations / 2);
  }
}

TEST(FuzzReaders, ColmapBinaryModel) { fuzz_colmap(ColmapFormat::kBinary, ".bin", 20); }
TEST(FuzzReaders, ColmapTextModel) { fuzz_colmap(ColmapFormat::kText, ".txt", 30); }

TEST(FuzzReaders, YamlConfiguration) {
  testing::TempDir dir;
  const std::string valid = read_file(testing::source_dir() / "config" / "default.yaml");
  ASSERT_FALSE(valid.empty());
  const fs::path file = dir / "mutant.yaml";
  fuzz_file("yaml", 40, valid, /*text=*/true, file, [&] {
    pipeline::PipelineConfig config;
    config.apply_file(file.string());
    config.validate();
  });
}

TEST(FuzzReaders, StanfordConf) {
  testing::TempDir dir;
  PointCloud scan = small_cloud();
  scan.normals.clear();
  write_point_cloud_ply(dir / "a.ply", scan, PlyFormat::kAscii);
  write_point_cloud_ply(dir / "b.ply", scan, PlyFormat::kBinaryLittleEndian);
  const std::string conf = "camera 0 0 1 0 0 0 1\nbmesh a.ply 0 0 0 0 0 0 1\nbmesh b.ply 0.1 -0.2 0.3 0 1 0 0\n";
  fuzz_file("stanford-conf", 50, conf, /*text=*/true, dir / "scans.conf",
            [&] { check_cloud(recon::load_stanford_scans(dir / "scans.conf", null_reporter())); });
  // A damaged scan behind a valid .conf.
  write_file(dir / "scans.conf", conf);
  const std::string valid_scan = read_file(dir / "b.ply");
  fuzz_file(
      "stanford-scan", 51, valid_scan, /*text=*/false, dir / "b.ply",
      [&] { check_cloud(recon::load_stanford_scans(dir / "scans.conf", null_reporter())); }, kIterations / 2);
}

TEST(FuzzReaders, PhotoHeaders) {
  // Our own readers of JPEG structure and EXIF, on every mutant.
  const cv::Mat image = sfm::testing::gradient_image(64, 48);
  const auto exif = sfm::testing::jpeg_with_exif(image, 6, 35.0, /*little_endian=*/true);
  const std::string valid(exif.begin(), exif.end());
  const std::uint64_t seed = testing::fuzz_seed() * 1000003 + 60;
  Mutator mutator(seed);
  const int n = testing::fuzz_iterations(kIterations) * 4;
  for (int i = 0; i < n; ++i) {
    const std::string mutant = mutator.mutate(valid, /*text=*/false);
    const std::vector<std::uint8_t> bytes(mutant.begin(), mutant.end());
    expect_documented_outcome("exif", seed, i, mutant, [&] {
      const sfm::ExifInfo info = sfm::parse_jpeg_exif(bytes);
      ASSERT_TRUE(info.orientation >= 1 && info.orientation <= 8);
      if (info.focal_length_mm) {
        ASSERT_TRUE(std::isfinite(*info.focal_length_mm));
      }
      sfm::jpeg_is_complete(bytes);
    });
  }
}

TEST(FuzzReaders, PhotoFolders) {
  // The whole photo check (decoders and EXIF included) on folders of mutated
  // JPEG, PNG, TIFF and HEIC photos: skipped with a reason, or staged.
  testing::TempDir dir;
  const cv::Mat image = sfm::testing::gradient_image(64, 48);
  std::vector<std::pair<std::string, std::string>> valid;
  for (const char* ext : {".jpg", ".png", ".tif"}) {
    std::vector<std::uint8_t> bytes;
    ASSERT_TRUE(cv::imencode(ext, image, bytes));
    valid.emplace_back(ext, std::string(bytes.begin(), bytes.end()));
  }
  sfm::testing::PhoneExif exif;
  exif.latitude_deg = 46.5;
  exif.longitude_deg = 6.6;
  const auto jpeg = sfm::testing::jpeg_with_phone_exif(image, exif);
  valid.emplace_back(".jpg", std::string(jpeg.begin(), jpeg.end()));
  const auto heic = sfm::testing::heic_with_exif(image, 6, exif);  // empty without a HEVC encoder
  if (!heic.empty()) valid.emplace_back(".heic", std::string(heic.begin(), heic.end()));
  const std::uint64_t seed = testing::fuzz_seed() * 1000003 + 70;
  Mutator mutator(seed);
  sfm::SfmOptions options;
  options.min_image_size = 16;
  const int n = testing::fuzz_iterations(kIterations) / 6;
  for (int i = 0; i < n; ++i) {
    fs::remove_all(dir / "photos");
    fs::remove_all(dir / "staged");
    fs::create_directories(dir / "photos");
    std::string all;
    for (std::size_t k = 0; k < valid.size(); ++k) {
      const std::string mutant = mutator.mutate(valid[k].second, /*text=*/false);
      std::string name = "p";  // appended: GCC 12 warns (-Wrestrict) on "p" + std::to_string(k)
      name += std::to_string(k) + valid[k].first;
      write_file(dir / "photos" / name, mutant);
      all += mutant;
    }
    expect_documented_outcome("photos", seed, i, all,
                              [&] { sfm::prepare_images(dir / "photos", dir / "staged", options, null_reporter()); });
  }
}

}  // namespace
}  // namespace hos
