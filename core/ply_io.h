// PLY reading and writing (ASCII, binary little and big endian) for point sets
// and triangle meshes. Readers accept any property order and the common type
// names (char/uchar/short/ushort/int/uint/float/double and int8..float64).
#pragma once

#include <filesystem>

#include "core/types.h"

namespace hos {

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

struct PlyReadReport {
  std::size_t num_skipped_nonfinite = 0;   // vertices dropped for NaN/Inf coordinates
  std::size_t num_invalid_confidence = 0;  // NaN, infinite or negative confidences, read as 0
};

// Reads the "vertex" element: x y z, optional nx ny nz, red green blue
// (or r g b / diffuse_*), confidence (or "quality"/"value"), other scalars into
// PointCloud::scalars. Vertices with non-finite coordinates are dropped and
// counted in report; NaN, infinite or negative confidences are read as 0
// and counted; non-finite normals are read as zero (no orientation). Throws InputError for a
// missing file, a malformed or truncated header, or data that does not match the header's counts.
PointCloud read_point_cloud_ply(const std::filesystem::path& path, PlyReadReport* report = nullptr);

// Reads vertices (as above) and the "face" element (vertex_indices or
// vertex_index lists; polygons are fan-triangulated). A mesh with non-finite
// vertices is an InputError (faces would dangle).
TriangleMesh read_mesh_ply(const std::filesystem::path& path);

// Writes atomically (temporary file, then rename). Throws OutputError.
void write_point_cloud_ply(const std::filesystem::path& path,
                           const PointCloud& cloud,
                           PlyFormat format = PlyFormat::kBinaryLittleEndian);
void write_mesh_ply(const std::filesystem::path& path,
                    const TriangleMesh& mesh,
                    PlyFormat format = PlyFormat::kBinaryLittleEndian);

}  // namespace hos
