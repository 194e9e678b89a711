#include "texture/texture_options.h"

#include "core/error.h"
#include "core/option_set.h"
#include "texture/placement.h"

namespace hos::texture {

void TextureOptions::validate() const {
  check_option_table("texture", *this);
  if (scale_distance != "none") parse_scale_distance(scale_distance);  // throws ConfigError
  if (2 * padding + 1 >= atlas_size) {
    throw ConfigError("texture.padding", "must be smaller than half of texture.atlas_size");
  }
}

void register_options(OptionSet& set, TextureOptions& o) {
  set.add_zero_or("max_faces", o.max_faces, "decimate to at most this many faces first; 0 = keep", 4, 2000000000);
  set.add("decimation_error_px", o.decimation_error_px,
          "decimate first where the surface moves by at most this many of the finest photo pixels on it "
          "(meshoptimizer's quadric error; 0 = keep every face)",
          0.0, 100.0);
  set.add("max_view_angle_deg", o.max_view_angle_deg,
          "largest angle between face normal and viewing ray for a view to count", 1.0, 89.9);
  set.add("depth_tolerance", o.depth_tolerance, "relative depth tolerance of the occlusion test", 0.0, 1.0);
  set.add("min_projected_area_px", o.min_projected_area_px,
          "ignore views where a face covers fewer pixels (unless no other sees it)", 0.0, 1e6);
  set.add("smoothness", o.smoothness, "Potts weight of the view-selection smoothness term", 0.0, 1000.0);
  set.add("gradient_floor", o.gradient_floor,
          "added per pixel to the gradient magnitude so flat regions prefer close views", 0.0, 1000.0);
  set.add("expansion_sweeps", o.expansion_sweeps, "alpha-expansion sweeps over all views", 0, 100);
  set.add("outlier_rejection", o.outlier_rejection,
          "drop views whose face colour disagrees with the others (moving objects)");
  set.add("outlier_threshold", o.outlier_threshold,
          "colour distance (8-bit RGB) from the robust mode beyond which a view is dropped", 1.0, 500.0);
  set.add("outlier_min_views", o.outlier_min_views, "faces seen by fewer views are not checked", 2, 1000);
  set.add("exposure_compensation", o.exposure_compensation,
          "estimate and undo per-image RGB gains (exposure, white balance; robust, Ceres)");
  set.add("global_leveling", o.global_leveling,
          "global seam leveling: per-vertex additive colour offsets (Waechter 2014)");
  set.add("leveling_regularization", o.leveling_regularization,
          "lambda: in-patch offset smoothness is weighted 1/lambda (smaller = smoother)", 1e-4, 1e4);
  set.add("local_blending", o.local_blending, "blend the two views' colours along seams");
  set.add("seam_blend_texels", o.seam_blend_texels, "width of the blending band on each side (texels)", 0.0, 64.0);
  set.add_enum("unseen", o.unseen,
               {{"diffuse", UnseenFaces::kDiffuse}, {"grey", UnseenFaces::kGrey}, {"mark", UnseenFaces::kMark}},
               "colour of faces no photo sees: diffuse (from the seen faces around them, over the surface), grey, "
               "or mark (magenta, to show where the photos do not reach)");
  set.add("min_chart_area_px", o.min_chart_area_px,
          "charts smaller than this (photo pixels) take a neighbouring chart's view where it sees them as well; "
          "0 = off",
          0.0, 1e9);
  set.add("atlas_size", o.atlas_size, "maximum atlas width and height (pixels)", 64, 16384);
  set.add("padding", o.padding,
          "free texels between charts (each side's colour dilated into them: 2 keeps bilinear lookups apart)", 0, 64);
  set.add("texel_scale", o.texel_scale, "atlas texels per source image pixel", 0.01, 4.0);
  set.add("max_atlases", o.max_atlases, "largest number of atlas images; beyond, texels shrink", 1, 1024);
  set.add_choice("image_format", o.image_format, {"jpeg", "png"}, "atlas image encoding (JPEG 4:4:4 or PNG)");
  set.add("jpeg_quality", o.jpeg_quality, "JPEG quality of the atlases", 1, 100);
  set.add_choice("mesh_compression", o.mesh_compression, {"none", "quantized", "meshopt"},
                 "glTF vertex data: none = 32-bit floats; quantized = KHR_mesh_quantization (16-bit positions and UVs, "
                 "8-bit normals); meshopt = quantized and EXT_meshopt_compression (meshoptimizer's codecs); both are "
                 "required extensions that Debian's Blender does not read");
  set.add_zero_or("preview_max_faces", o.preview_max_faces,
                  "faces of the preview model STEM.preview.glb written beside the output; 0 = no preview", 4,
                  2000000000);
  set.add("preview_atlas_size", o.preview_atlas_size, "largest side of the preview's single JPEG atlas (pixels)", 64,
          16384);
  set.add_choice("up_axis", o.up_axis, {"cameras", "none"},
                 "root node: cameras = upright (gravity, ground or GPS), centred, on y = 0; none = identity");
  set.add("scale_distance", o.scale_distance,
          "'A.jpg B.jpg METRES': two photos' camera centres measured on site set the scale; none = GPS or arbitrary");
  set.add_flag("--max-faces", "max_faces");
  set.add_flag("--atlas-size", "atlas_size");
  set.add_flag("--image-format", "image_format");
}

}  // namespace hos::texture
