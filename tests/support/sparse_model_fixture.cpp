#include "tests/support/sparse_model_fixture.h"

namespace hos::testing {

SparseModel small_sparse_model() {
  SparseModel m;
  m.cameras[1] = Camera::pinhole(1, 640, 480, 500.5, 501.25, 320, 240);
  Camera distorted;
  distorted.id = 2;
  distorted.model = CameraModel::kOpenCV;
  distorted.width = 800;
  distorted.height = 600;
  distorted.params = {700, 701, 400, 300, -0.1, 0.02, 0.001, -0.003};
  m.cameras[2] = distorted;
  for (int id : {3, 7}) {
    ImageRecord im;
    im.id = id;
    im.camera_id = id == 3 ? 1 : 2;
    im.name = "img_" + std::to_string(id) + ".jpg";
    im.cam_from_world_rotation = Eigen::Quaterniond(0.9, 0.1 * id, -0.2, 0.3).normalized();
    im.cam_from_world_translation = Eigen::Vector3d(0.5 * id, -1.0, 2.5);
    im.keypoints = {{Eigen::Vector2d(10.5, 20.25), 11}, {Eigen::Vector2d(100, 200), -1}};
    m.images[id] = im;
  }
  Point3D p;
  p.id = 11;
  p.xyz = Eigen::Vector3d(0.25, -1.5, 4.0);
  p.color = {10, 200, 30};
  p.error = 0.75;
  p.track = {{3, 0}, {7, 0}};
  m.points[11] = p;
  return m;
}

}  // namespace hos::testing
