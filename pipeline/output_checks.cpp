#include "pipeline/output_checks.h"

#include <cmath>
#include <system_error>

#include "core/atomic_file.h"
#include "core/disk_space.h"
#include "core/error.h"
#include "texture/model_writer.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

std::string megabytes(std::uintmax_t bytes) {
  return std::to_string(std::llround(static_cast<double>(bytes) / (1024.0 * 1024.0))) + " MB";
}

// Lexically normalised absolute path, for comparing locations.
fs::path normalised(const fs::path& p) {
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(p, ec);
  return (ec ? fs::absolute(p) : canonical).lexically_normal();
}

bool is_inside(const fs::path& path, const fs::path& folder) {
  const fs::path rel = normalised(path).lexically_relative(normalised(folder));
  return !rel.empty() && *rel.begin() != "..";
}

}  // namespace

void warn_if_low_space(const fs::path& folder, std::uintmax_t needed, const std::string& stage, Reporter& reporter) {
  const DiskSpace disk = disk_space(folder);
  if (!disk.known || disk.free_bytes >= needed) return;
  reporter.warn("the disk mounted at " + disk.mount_point.string() + " has " + megabytes(disk.free_bytes) +
                " free; the " + stage + " stage may need about " + megabytes(needed) + " in " + folder.string());
}

void copy_result(const fs::path& model, const fs::path& output) {
  // Another format than the workspace's .glb: written from it (same atlases).
  if (texture::model_format_of(output) != texture::ModelFormat::kGlb) return texture::convert_model(model, output);
  write_atomically(output, [&](const fs::path& tmp) {
    std::error_code ec;
    fs::copy_file(model, tmp, ec);
    if (ec) {
      throw OutputError(
          output.string(),
          ec.message() + " (" + describe_disk(output.has_parent_path() ? output.parent_path() : ".") + ")");
    }
  });
}

std::vector<fs::path> pipeline_files_in_photos(const fs::path& photos,
                                               const fs::path& output,
                                               const fs::path& workspace) {
  std::vector<fs::path> inside;
  for (const fs::path& p : {output, workspace}) {
    if (is_inside(p, photos)) inside.push_back(normalised(p));
  }
  return inside;
}

std::string damaged_intermediate_hint(const std::string& producer) {
  return "if the " + producer +
         " stage's result in the workspace was damaged or edited, re-create it with --force "
         "--from " +
         producer;
}

}  // namespace hos::pipeline
