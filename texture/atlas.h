// Texture atlas: every chart is projected with its view's camera and turned
// so its minimum-area rectangle lies along the axes (a similarity of the
// photo's pixels, so texels are resampled once); the charts' footprints (the
// texels they cover) are packed by shape, in quarter turns, options.padding
// free texels apart, into pages of at most options.atlas_size
// (atlas_packing.h), and texels are filled from the photo (times the
// exposure gain, plus the seam-leveling offset interpolated over each face).
// The charts' texels are dilated into the gaps between them, each chart's
// own colour meeting its neighbour's halfway, so bilinear lookups (one ring)
// and the first mipmap levels do not mix neighbouring charts. Faces no view
// sees share one texel per distinct colour.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"
#include "texture/charts.h"
#include "texture/mesh_topology.h"
#include "texture/seam_leveling.h"
#include "texture/texture_options.h"
#include "texture/texture_view.h"
#include "texture/textured_mesh.h"
#include "texture/visibility.h"

namespace hos::texture {

// A flat-coloured patch for a face that no view sees.
struct FlatFace {
  int face = -1;
  Eigen::Vector3f rgb = Eigen::Vector3f::Zero();
};

struct Atlas {
  std::vector<cv::Mat> pages;  // CV_8UC3, BGR
  // Per chart: its page and the UV (glTF: u right, v down) of each chart vertex.
  std::vector<int> chart_page;
  std::vector<std::vector<Eigen::Vector2f>> chart_uvs;
  // Per flat face: its page and the UV of its patch centre.
  std::vector<int> flat_page;
  std::vector<Eigen::Vector2f> flat_uvs;
  double texel_scale = 1.0;  // texels per photo pixel finally used
};

// With options.local_blending, texels within options.seam_blend_texels of a
// seam edge are mixed with the neighbouring chart's view (and offsets) at the
// same surface point: half-and-half on the seam, fading out with distance;
// only if that view is among the face's candidates (visible, consistent).
Atlas build_atlas(const TriangleMesh& mesh,
                  const MeshTopology& topology,
                  const FaceViewCandidates& candidates,
                  const std::vector<Chart>& charts,
                  const std::vector<TextureView>& views,
                  const std::vector<Eigen::Vector3f>& gains,
                  const SeamLeveling& leveling,
                  const std::vector<FlatFace>& flat_faces,
                  const TextureOptions& options,
                  Reporter& reporter);

// The share of the atlas texels whose centre lies in a textured triangle
// (UV triangles of zero area, such as the flat patches of unseen faces,
// cover nothing): covered texels over all texels of all pages.
double atlas_coverage(const TexturedMesh& mesh);

}  // namespace hos::texture
