#include "eval/gltf_reader.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos::eval {
namespace {

template <class T>
int append_view(tinygltf::Model& m, const std::vector<T>& data) {
  auto& buf = m.buffers[0].data;
  while (buf.size() % 4) buf.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buf.size();
  view.byteLength = data.size() * sizeof(T);
  buf.resize(buf.size() + view.byteLength);
  std::memcpy(buf.data() + view.byteOffset, data.data(), view.byteLength);
  m.bufferViews.push_back(view);
  return static_cast<int>(m.bufferViews.size()) - 1;
}

int append_accessor(tinygltf::Model& m, int view, int component, int type, std::size_t count) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = component;
  a.type = type;
  a.count = count;
  m.accessors.push_back(a);
  return static_cast<int>(m.accessors.size()) - 1;
}

// Two triangles forming a quad split along a seam (6 vertices, 4 positions),
// a 4x2 PNG texture, and a root node translating by (0, 0, 5).
void write_test_glb(const std::filesystem::path& path) {
  tinygltf::Model m;
  m.buffers.resize(1);
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 1, 1, 0, 0, 0};
  const std::vector<std::uint32_t> idx = {0, 1, 2, 3, 4, 5};
  cv::Mat tex(2, 4, CV_8UC3, cv::Scalar(10, 20, 200));  // BGR: red
  std::vector<unsigned char> png;
  cv::imencode(".png", tex, png);
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] =
      append_accessor(m, append_view(m, pos), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 6);
  m.accessors.back().minValues = {0, 0, 0};
  m.accessors.back().maxValues = {1, 1, 0};
  prim.attributes["TEXCOORD_0"] =
      append_accessor(m, append_view(m, uv), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, 6);
  prim.indices = append_accessor(m, append_view(m, idx), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, 6);
  tinygltf::Image image;
  image.bufferView = append_view(m, png);
  image.mimeType = "image/png";
  m.images.push_back(image);
  tinygltf::Texture texture;
  texture.source = 0;
  m.textures.push_back(texture);
  tinygltf::Material material;
  material.pbrMetallicRoughness.baseColorTexture.index = 0;
  m.materials.push_back(material);
  prim.material = 0;
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(prim);
  m.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.matrix = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1};
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  m.asset.version = "2.0";
  m.buffers[0].data.resize((m.buffers[0].data.size() + 3) / 4 * 4);
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&m, path.string(), true, true, false, true));
}

TEST(GltfReader, ReadsTransformedWeldedTexturedMesh) {
  hos::testing::TempDir dir;
  write_test_glb(dir / "q.glb");
  // The scene frame applies the root node's matrix (a translation by 5 in z);
  // the model frame, hos-texture's convention, leaves the root's matrix out.
  const render::RenderObject o = read_glb(dir / "q.glb", GlbFrame::kScene);
  ASSERT_EQ(o.mesh.faces.size(), 2u);
  EXPECT_EQ(o.mesh.vertices.size(), 4u);  // the seam's duplicated positions are welded
  for (const auto& v : o.mesh.vertices) EXPECT_FLOAT_EQ(v.z(), 5.0f);
  const render::RenderObject model_frame = read_glb(dir / "q.glb");
  ASSERT_EQ(model_frame.mesh.vertices.size(), 4u);
  for (const auto& v : model_frame.mesh.vertices) EXPECT_FLOAT_EQ(v.z(), 0.0f);
  ASSERT_EQ(o.material.textures.size(), 1u);
  EXPECT_EQ(o.material.textures[0].size(), cv::Size(4, 2));
  EXPECT_EQ(o.material.textures[0].at<cv::Vec3b>(1, 3), cv::Vec3b(10, 20, 200));
  ASSERT_EQ(o.material.corner_uvs.size(), 6u);
  EXPECT_EQ(o.material.corner_uvs[2], Eigen::Vector2f(1, 0));
  EXPECT_EQ(o.material.face_texture, std::vector<int>({0, 0}));
}

TEST(GltfReader, MissingOrMalformedFileNamesIt) {
  hos::testing::TempDir dir;
  EXPECT_THROW(read_glb(dir / "none.glb"), InputError);
  { std::ofstream(dir / "bad.glb") << "not a glb"; }
  try {
    read_glb(dir / "bad.glb");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.glb"), std::string::npos);
  }
}

}  // namespace
}  // namespace hos::eval
