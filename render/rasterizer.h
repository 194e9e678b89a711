// A deterministic CPU z-buffer rasterizer: triangle meshes with a material,
// seen through a COLMAP camera, give a colour image, depth, mask, normals and
// face ids. Used by hos-synth (photos with known truth), by the texture tests
// and by hos-eval (re-rendering a textured result from held-out views).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "core/camera.h"
#include "core/sparse_model.h"
#include "core/types.h"

namespace hos::render {

// Albedo of a point on the surface, in linear [0, 1] RGB.
using ProceduralAlbedo = std::function<Eigen::Vector3f(const Eigen::Vector3f& x_in_world)>;

// How a mesh is coloured. Exactly one source is used, in this order:
// textures (if non-empty), procedural (if set), mesh.colors (if non-empty),
// else constant_albedo.
struct Material {
  // UV texturing as in glTF: corner_uvs has 3 entries per face (face f, corner
  // c at index 3f+c), u right, v DOWN from the top-left of the image;
  // face_texture gives the texture index of each face (empty: all 0).
  std::vector<cv::Mat> textures;  // CV_8UC3, BGR (OpenCV order)
  std::vector<Eigen::Vector2f> corner_uvs;
  std::vector<int> face_texture;
  ProceduralAlbedo procedural;
  Eigen::Vector3f constant_albedo = Eigen::Vector3f::Constant(0.7f);
};

struct RenderObject {
  TriangleMesh mesh;  // faces counter-clockwise seen from outside
  Material material;
};

// Lambertian shading with a directional light fixed in the WORLD frame (not a
// headlight), so the shaded colour of a surface point is the same in every
// view and can be baked into a texture. unlit renders the albedo as is.
struct Lighting {
  bool unlit = false;
  Eigen::Vector3f direction_to_light = Eigen::Vector3f(0.3f, -0.8f, -0.5f).normalized();
  float ambient = 0.35f;
  float diffuse = 0.65f;
};

struct RenderOptions {
  int supersampling = 2;  // samples per pixel per axis (1 = none)
  Lighting lighting;
  Eigen::Vector3f background = Eigen::Vector3f::Zero();  // linear RGB
  bool cull_back_faces = false;                          // closed meshes look the same either way
  // Multiplies the final colour (e.g. 1.3 for a "30% brighter" photo).
  float exposure_gain = 1.0f;
};

// All images are camera.height x camera.width.
struct RenderedView {
  cv::Mat color;      // CV_8UC3, BGR, sRGB-encoded 8 bit
  cv::Mat depth;      // CV_32F, camera-frame z of the nearest surface, 0 where empty
  cv::Mat mask;       // CV_8U, 255 where any surface covers the pixel centre
  cv::Mat normal;     // CV_32FC3, world-frame unit normal (x, y, z), 0 where empty
  cv::Mat face_id;    // CV_32S, index into the concatenated faces of all objects, -1 where empty
  cv::Mat object_id;  // CV_32S, index of the object, -1 where empty
};

// Renders objects from one posed camera. Distortion parameters of the camera
// are honoured by projecting vertices with Camera::project per pixel sample
// only for pinhole models; distorted models are rendered as their pinhole part.
// Faces with a non-finite vertex are skipped. Results do not depend on the
// number of OpenMP threads.
RenderedView render_view(const std::vector<RenderObject>& objects,
                         const Camera& camera,
                         const ImageRecord& pose,
                         const RenderOptions& options = {});

}  // namespace hos::render
