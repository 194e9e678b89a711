// pipeline/slurm/job_estimates.*: the memory and time a cluster job asks for.
// The time estimates must grow with what they depend on, never fall below
// the floor, give way to the time option, and be text sbatch accepts.
#include "pipeline/slurm/job_estimates.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <regex>

#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;

// sbatch --time's forms with seconds: HH:MM:SS and D-HH:MM:SS.
bool is_sbatch_time(const std::string& text) {
  return std::regex_match(text, std::regex(R"((\d+-)?([01]\d|2[0-3]):[0-5]\d:[0-5]\d)"));
}

// Whole seconds of "D-HH:MM:SS" or "HH:MM:SS" (test-side parser).
double seconds_of(const std::string& text) {
  std::smatch m;
  EXPECT_TRUE(std::regex_match(text, m, std::regex(R"((?:(\d+)-)?(\d+):(\d+):(\d+))"))) << text;
  const double days = m[1].matched ? std::stod(m[1]) : 0.0;
  return ((days * 24 + std::stod(m[2])) * 60 + std::stod(m[3])) * 60 + std::stod(m[4]);
}

RunBounds bounds(int views, double megapixels) {
  RunBounds b;
  b.views = views;
  b.photo_megapixels = megapixels;
  return b;
}

TEST(JobEstimates, TimeTextIsWholeMinutesInSbatchForm) {
  for (double seconds : {0.0, 1.0, 59.0, 600.0, 3599.0, 86399.0, 86400.0, 200000.0, 5e6}) {
    const std::string text = slurm_time_text(seconds);
    EXPECT_TRUE(is_sbatch_time(text)) << seconds << " -> " << text;
    EXPECT_GE(seconds_of(text), seconds) << text;
    EXPECT_LT(seconds_of(text), seconds + 60.0) << text;
  }
  EXPECT_EQ(slurm_time_text(90061.0), "1-01:02:00");
  EXPECT_EQ(slurm_time_text(61.0), "00:02:00");
}

TEST(JobEstimates, CpuTimeGrowsWithViewsPixelsFacesAndGrid) {
  PipelineConfig config;
  config.apply_assignment("mvs.max_image_size=2048");
  const RunBounds small = bounds(50, 6.0), more_views = bounds(100, 6.0), larger_photos = bounds(50, 24.0);
  EXPECT_GT(job_cpu_seconds("sfm", config, more_views, 1), job_cpu_seconds("sfm", config, small, 1));
  for (const char* job : {"mvs-depth", "texture-views"}) {
    EXPECT_GT(job_cpu_seconds(job, config, small, 10), job_cpu_seconds(job, config, small, 5)) << job;
    EXPECT_GT(job_cpu_seconds(job, config, larger_photos, 5), job_cpu_seconds(job, config, bounds(50, 1.0), 5)) << job;
  }
  for (const char* job : {"mvs-fuse", "refine", "texture-atlas"}) {
    EXPECT_GT(job_cpu_seconds(job, config, more_views, 1), job_cpu_seconds(job, config, small, 1)) << job;
  }
  EXPECT_GT(job_cpu_seconds("refine", config, larger_photos, 1), job_cpu_seconds("refine", config, small, 1));

  // The matching size the options allow.
  PipelineConfig finer;
  finer.apply_assignment("mvs.max_image_size=4096");
  EXPECT_GT(job_cpu_seconds("mvs-depth", finer, larger_photos, 5),
            job_cpu_seconds("mvs-depth", config, larger_photos, 5));
  // Texture's faces: refine's budget, or texture's own decimation bound.
  PipelineConfig more_faces;
  more_faces.apply_assignment("refine.max_faces=1000000");
  for (const char* job : {"texture-views", "texture-atlas"}) {
    EXPECT_GT(job_cpu_seconds(job, more_faces, small, 5), job_cpu_seconds(job, config, small, 5)) << job;
  }
  PipelineConfig decimated;
  decimated.apply_assignment("texture.max_faces=20000");
  EXPECT_LT(job_cpu_seconds("texture-atlas", decimated, small, 5), job_cpu_seconds("texture-atlas", config, small, 5));
  // recon: a set grid, finer takes longer.
  PipelineConfig grid512, grid1024;
  grid512.apply_assignment("recon.resolution=512");
  grid1024.apply_assignment("recon.resolution=1024");
  EXPECT_GT(job_cpu_seconds("recon", grid1024, small, 1), job_cpu_seconds("recon", grid512, small, 1));
  EXPECT_GT(job_cpu_seconds("recon", grid512, small, 1), 0.0);
  // A tile may span most of the grid: each tile task and the join get the
  // whole grid's time.
  for (const char* job : {"recon-tiles", "recon-join"}) {
    EXPECT_EQ(job_cpu_seconds(job, grid512, small, 0), job_cpu_seconds("recon", grid512, small, 1)) << job;
  }
}

TEST(JobEstimates, NoEstimateWithoutWhatItNeeds) {
  PipelineConfig config;
  // recon's grid follows the points' density by default: unknown before mvs.
  EXPECT_EQ(job_cpu_seconds("recon", config, bounds(50, 6.0), 1), 0.0);
  EXPECT_EQ(job_time_limit("recon", config, bounds(50, 6.0), 1, ""), "");
  // Photo size unknown: no refine or texture estimate.
  EXPECT_EQ(job_cpu_seconds("texture-views", config, bounds(50, 0.0), 5), 0.0);
  EXPECT_EQ(job_cpu_seconds("refine", config, bounds(50, 0.0), 1), 0.0);
  // Refine off and no decimation: texture's faces are unbounded.
  config.apply_assignment("refine.enabled=false");
  EXPECT_EQ(job_cpu_seconds("texture-atlas", config, bounds(50, 6.0), 1), 0.0);
}

TEST(JobEstimates, TimeLimitIsTheEstimateWithMarginAtLeastTheFloorUnlessOverridden) {
  PipelineConfig config;
  const RunBounds tiny = bounds(3, 0.3);
  EXPECT_EQ(seconds_of(job_time_limit("sfm", config, tiny, 1, "")), kMinTimeSeconds);
  const RunBounds large = bounds(2000, 24.0);
  for (const char* job : {"sfm", "mvs-depth", "mvs-fuse", "refine", "texture-views", "texture-atlas"}) {
    const std::string limit = job_time_limit(job, config, large, 500, "");
    ASSERT_TRUE(is_sbatch_time(limit)) << job << ": " << limit;
    const double estimate = job_cpu_seconds(job, config, large, 500);
    EXPECT_GE(seconds_of(limit), std::max(kMinTimeSeconds, kTimeSafetyFactor * estimate)) << job;
    EXPECT_LT(seconds_of(limit), std::max(kMinTimeSeconds, kTimeSafetyFactor * estimate) + 60.0) << job;
    EXPECT_EQ(job_time_limit(job, config, large, 500, "7-00:00:00"), "7-00:00:00") << job;
  }
  EXPECT_EQ(job_time_limit("recon", config, large, 1, "02:00:00"), "02:00:00");
}

TEST(JobEstimates, RunBoundsCountThePhotosAndMeasureTheLargest) {
  hos::testing::TempDir dir("hos-job-estimates");
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  ASSERT_TRUE(cv::imwrite((photos / "small.jpg").string(), cv::Mat(120, 160, CV_8UC3, cv::Scalar(90, 40, 200))));
  ASSERT_TRUE(cv::imwrite((photos / "large.jpg").string(), cv::Mat(600, 800, CV_8UC3, cv::Scalar(10, 140, 60))));
  std::ofstream(photos / ".hidden") << "not counted";
  PipelineConfig config;
  const RunBounds b = run_bounds(photos, config);
  EXPECT_EQ(b.views, 2);
  // 800x600 read at 1/8: 100x75 stands for up to 808x608 pixels.
  EXPECT_GE(b.photo_megapixels, 0.48);
  EXPECT_LE(b.photo_megapixels, 808.0 * 608.0 / 1e6);
  // sfm downscales photos longer than its max_image_size: the bound follows.
  config.apply_assignment("sfm.max_image_size=400");
  EXPECT_NEAR(run_bounds(photos, config).photo_megapixels, 0.75 * 400 * 400 / 1e6, 1e-9);
}

TEST(JobEstimates, MemoryRequestsComeFromTheStagesOwnEstimates) {
  PipelineConfig config;
  const int depth = job_memory_mb("mvs-depth", config, 100, 3000);
  EXPECT_GT(depth, 512);
  config.apply_assignment("mvs.max_image_size=4096");
  EXPECT_GT(job_memory_mb("mvs-depth", config, 100, 3000), 2 * depth - 512);
  EXPECT_GT(job_memory_mb("mvs-fuse", config, 200, 3000), job_memory_mb("mvs-fuse", config, 100, 3000));
  EXPECT_EQ(job_memory_mb("recon", config, 100, 3000), 3000);  // no budget set: the default request
  config.apply_assignment("recon.max_memory_mb=8000");
  EXPECT_EQ(job_memory_mb("recon", config, 100, 3000), 8512);
  // hos-recon refuses a tile whose solve exceeds the budget: each tile
  // task, and the join, ask for the budget, not for the whole grid's estimate.
  EXPECT_EQ(job_memory_mb("recon-tiles", config, 100, 3000), 8512);
  EXPECT_EQ(job_memory_mb("recon-join", config, 100, 3000), 8512);
  EXPECT_EQ(job_memory_mb("sfm", config, 100, 3000), 3000);
}

}  // namespace
}  // namespace hos::pipeline
