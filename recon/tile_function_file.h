// The normalised implicit function of one tile of a tiled reconstruction, as
// `hos-recon --tile K --tile-dir DIR` writes it and `--join-tiles DIR` reads
// it (docs/scale.md): the values on the lattice nodes of the tile's extended
// box, so the join reads only the part of each tile a core needs.
//
// Layout (native byte order, as the machine that wrote it; clusters share one):
//   char[8]  tag "HOSTILEF"
//   uint32   format version (kTileFunctionVersion)
//   int32    tile index, int32 number of tiles
//   uint64   fingerprint of the run (tiled_run_fingerprint: samples, options,
//            lattice and every tile's boxes)
//   int32[6] the extended box: lo x y z, hi x y z (lattice nodes, inclusive)
//   float64  the tile's isovalue and gradient scale (for the log)
//   uint64   number of values n (the box's nodes)
//   n float32 normalised values, x fastest, then y, then z; NaN: no value
//            (outside the tile's band)
// and nothing after.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include "recon/tile_plan.h"

namespace hos::recon {

inline constexpr std::uint32_t kTileFunctionVersion = 1;

struct TileFunctionHeader {
  int tile = 0;
  int num_tiles = 0;
  std::uint64_t fingerprint = 0;
  NodeBox box;
  double isovalue = 0.0;
  double gradient_scale = 1.0;
};

// folder/tile-<K>.htf, K with four digits.
std::filesystem::path tile_function_file(const std::filesystem::path& folder, int tile);

// Writes the header and the box's values atomically (creating the folder).
// Throws OutputError.
void write_tile_function(const std::filesystem::path& file,
                         const TileFunctionHeader& header,
                         const std::vector<float>& values);

// A tile's file, opened and checked against what the run expects.
class TileFunctionReader {
 public:
  // Throws InputError naming the file when it is missing, not a tile file, of
  // another format version, truncated (or longer than its header says), or
  // written for another tile, run, set of points or options.
  TileFunctionReader(const std::filesystem::path& file, const TileFunctionHeader& expected);

  const TileFunctionHeader& header() const { return header_; }
  // The values on the nodes of part (inside the header's box), x fastest.
  // Throws InputError when the file cannot be read.
  std::vector<float> read(const NodeBox& part);

 private:
  std::filesystem::path file_;
  std::ifstream in_;
  TileFunctionHeader header_;
  std::streamoff data_offset_ = 0;
};

}  // namespace hos::recon
