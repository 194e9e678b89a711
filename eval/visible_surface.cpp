#include "eval/visible_surface.h"

#include "render/rasterizer.h"

namespace hos::eval {

TriangleMesh visible_part(const TriangleMesh& truth, const SparseModel& model, int min_views, Reporter& reporter) {
  std::vector<int> views_seeing(truth.num_faces(), 0);
  render::RenderObject object;
  object.mesh = truth;
  render::RenderOptions options;
  options.supersampling = 1;
  options.lighting.unlit = true;
  reporter.begin("visible surface", static_cast<std::int64_t>(model.images.size()));
  for (const auto& [id, image] : model.images) {
    reporter.throw_if_cancelled();
    const render::RenderedView view = render::render_view({object}, model.camera_of(image), image, options);
    std::vector<char> seen(truth.num_faces(), 0);
    for (int y = 0; y < view.face_id.rows; ++y) {
      for (int x = 0; x < view.face_id.cols; ++x) {
        const int f = view.face_id.at<int>(y, x);
        if (f >= 0) seen[f] = 1;
      }
    }
    for (std::size_t f = 0; f < seen.size(); ++f) views_seeing[f] += seen[f];
    reporter.advance();
  }
  reporter.end();
  TriangleMesh part = truth;
  part.faces.clear();
  for (std::size_t f = 0; f < truth.num_faces(); ++f) {
    if (views_seeing[f] >= min_views) part.faces.push_back(truth.faces[f]);
  }
  return part;
}

}  // namespace hos::eval
