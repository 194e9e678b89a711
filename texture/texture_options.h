// Options of the texture stage (YAML section "texture").
#pragma once

#include <string>

#include "core/option_set.h"

namespace hos::texture {

// How faces no photo sees are coloured (unseen_faces.h).
enum class UnseenFaces {
  kDiffuse,  // diffused over the surface from the seen faces around them
  kGrey,     // neutral grey
  kMark,     // magenta: shows where the photos do not reach
};

struct TextureOptions {
  // Decimate the mesh before texturing (quadric error metrics,
  // meshoptimizer): to at most max_faces faces (0 = no budget), and where the
  // surface moves by at most decimation_error_px times the finest photo
  // pixel on it (decimate.h's finest_pixel_size; 0 = no error-bounded
  // decimation). Refine leaves edges a few pixels long everywhere; flat
  // parts need far fewer faces to look the same.
  int max_faces = 0;
  double decimation_error_px = 0.5;

  // Visibility: a face is seen by a view if it faces the camera within
  // max_view_angle_deg and its centroid and three inner points pass the
  // depth test with this relative tolerance.
  double max_view_angle_deg = 80.0;
  double depth_tolerance = 0.01;
  // Faces whose projection is smaller than this (pixels) are not textured
  // from that view unless no other view sees them.
  double min_projected_area_px = 0.0;

  // View selection (Waechter et al. 2014, Sec. 4): data term = integral of the
  // gradient magnitude over the visible projected face (+ gradient_floor per
  // pixel so flat regions prefer close views) times the cosine of the viewing
  // angle; Potts smoothness with this weight; alpha-expansion sweeps.
  double smoothness = 0.5;
  double gradient_floor = 2.0;
  int expansion_sweeps = 3;  // at most; stops once fewer than 1% of the faces change

  // Photo-consistency (Waechter Sec. 4, "outlier removal"): a view whose mean
  // face colour (after exposure compensation) is farther than this (8-bit RGB
  // Euclidean distance) from the robust mode of the face's views is dropped.
  bool outlier_rejection = true;
  double outlier_threshold = 25.0;
  int outlier_min_views = 3;  // faces seen by fewer views are not checked

  // Per-image RGB gains (exposure and white balance; robust, Ceres), applied
  // before everything else.
  bool exposure_compensation = true;
  // Global seam leveling (Waechter Sec. 5.1): per-vertex per-view additive
  // offsets; leveling_regularization is Waechter's lambda: in-patch offset
  // differences are weighted 1/lambda, so smaller values give smoother offsets.
  bool global_leveling = true;
  double leveling_regularization = 0.1;

  // Local blending along seams: texels within seam_blend_texels of a seam
  // are mixed with the neighbouring view's colour (half-and-half on the seam).
  bool local_blending = true;
  double seam_blend_texels = 3.0;

  // Faces no photo sees (unseen_faces.h).
  UnseenFaces unseen = UnseenFaces::kDiffuse;

  // Charts covering fewer photo pixels than this in their view take a
  // neighbouring chart's view where it sees them as well (charts.h): fewer,
  // larger charts pack better. 0 keeps the view selection's charts.
  double min_chart_area_px = 400.0;

  // Atlas: maximum size (pixels, square), free texels between two charts
  // (filled with each chart's colour from both sides, so at 2 bilinear
  // lookups and the first mipmap level do not mix neighbouring charts),
  // texels per source pixel.
  int atlas_size = 4096;
  int padding = 2;
  double texel_scale = 1.0;
  int max_atlases = 16;  // if more would be needed, texel_scale shrinks

  // Atlas images: JPEG (4:4:4) at this quality costs at most 0.1 dB of
  // held-out PSNR against PNG (docs/texture.md).
  std::string image_format = "jpeg";  // jpeg | png
  int jpeg_quality = 95;
  // glTF vertex data: "none" (32-bit floats), "quantized"
  // (KHR_mesh_quantization) or "meshopt" (quantized, then
  // EXT_meshopt_compression). Both are required extensions: Blender's
  // importer in Debian reads neither; three.js, Babylon.js and model-viewer
  // read both (model-viewer once given its meshopt decoder's location).
  std::string mesh_compression = "none";

  // Preview model (texture/decimate.h): STEM.preview.glb beside the output
  // STEM.EXT, at most preview_max_faces faces on one JPEG atlas of at most
  // preview_atlas_size texels per side, its mesh compressed whatever
  // mesh_compression says (it is for web viewers); preview_max_faces 0
  // writes none.
  int preview_max_faces = 150000;
  int preview_atlas_size = 2048;

  // The glTF root node (texture/placement.h): "cameras" stands the model
  // upright (vertical from the cameras' level x axes, the ground plane or
  // GPS), centred on its footprint, on y = 0, in metres when GPS or
  // scale_distance allow; "none" keeps the SfM frame.
  std::string up_axis = "cameras";
  // "A.jpg B.jpg METRES": two photos' camera centres measured on site set
  // the scale (names without spaces); "none": GPS or arbitrary units.
  std::string scale_distance = "none";

  // Throws ConfigError naming the key and the allowed values.
  void validate() const;
};

void register_options(OptionSet& set, TextureOptions& options);

}  // namespace hos::texture
