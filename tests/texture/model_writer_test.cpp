// Every output format read back by a reader that is not the writer's code:
// the Khronos validator for .gltf, and small independent OBJ and PLY readers
// here (as MeshLab reads them: OBJ/MTL map_Kd; PLY "comment TextureFile",
// per-face texcoord and texnumber, v up from the bottom).
#include "texture/model_writer.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/error.h"
#include "tests/support/test_support.h"
#include "tests/texture/scene_fixtures.h"

namespace hos::texture {
namespace {

namespace fs = std::filesystem;

// The textured sphere with a root matrix the OBJ and PLY positions must carry.
TexturedMesh shifted_sphere(int atlas_size) {
  TexturedMesh out = testing::textured_sphere(atlas_size);
  out.root_matrix = Eigen::Matrix4d::Identity();
  out.root_matrix(1, 3) = 2.5;
  return out;
}

// What a reader found: positions, per-corner UVs (v up) with their page,
// and the atlas images it loaded.
struct ReadModel {
  std::vector<Eigen::Vector3f> positions;
  std::vector<std::array<int, 3>> faces;
  std::vector<std::array<Eigen::Vector2f, 3>> face_uvs;
  std::vector<int> face_page;
  std::vector<cv::Mat> pages;
  std::vector<cv::Vec3b> colours;  // PLY vertex colours (RGB)
};

ReadModel read_obj(const fs::path& path) {
  ReadModel out;
  std::ifstream in(path);
  std::string line, mtllib;
  std::vector<Eigen::Vector2f> vt;
  std::map<std::string, int> page_of_material;
  int page = -1;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "mtllib") {
      s >> mtllib;
      std::ifstream mtl(path.parent_path() / mtllib);
      std::string m, name;
      while (std::getline(mtl, m)) {
        std::istringstream ms(m);
        std::string key, value;
        ms >> key >> value;
        if (key == "newmtl") name = value;
        if (key == "map_Kd") {
          page_of_material[name] = static_cast<int>(out.pages.size());
          out.pages.push_back(cv::imread((path.parent_path() / value).string()));
        }
      }
    } else if (tag == "v") {
      Eigen::Vector3f p;
      s >> p.x() >> p.y() >> p.z();
      out.positions.push_back(p);
    } else if (tag == "vt") {
      Eigen::Vector2f t;
      s >> t.x() >> t.y();
      vt.push_back(t);
    } else if (tag == "usemtl") {
      std::string name;
      s >> name;
      page = page_of_material.at(name);
    } else if (tag == "f") {
      std::array<int, 3> f;
      std::array<Eigen::Vector2f, 3> uv;
      for (int c = 0; c < 3; ++c) {
        std::string corner;
        s >> corner;
        const int v = std::stoi(corner.substr(0, corner.find('/')));
        const int t = std::stoi(corner.substr(corner.find('/') + 1));
        f[c] = v - 1;
        uv[c] = vt.at(t - 1);
      }
      out.faces.push_back(f);
      out.face_uvs.push_back(uv);
      out.face_page.push_back(page);
    }
  }
  return out;
}

template <typename T>
T take(std::istream& in) {
  T value;
  in.read(reinterpret_cast<char*>(&value), sizeof(T));
  return value;
}

// Reads exactly the binary layout MeshLab's texture PLY files use; fails the
// test on another header.
ReadModel read_ply(const fs::path& path) {
  ReadModel out;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t vertices = 0, faces = 0;
  std::vector<std::string> vertex_properties;
  bool in_vertex = false;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream s(line);
    std::string a, b, c;
    s >> a >> b >> c;
    if (a == "comment" && b == "TextureFile") out.pages.push_back(cv::imread((path.parent_path() / c).string()));
    if (a == "format") {
      EXPECT_EQ(b, "binary_little_endian");
    }
    if (a == "element") {
      in_vertex = b == "vertex";
      (in_vertex ? vertices : faces) = std::stoul(c);
    }
    if (a == "property" && in_vertex) vertex_properties.push_back(c);
  }
  EXPECT_EQ(vertex_properties, (std::vector<std::string>{"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"}));
  for (std::size_t v = 0; v < vertices; ++v) {
    Eigen::Vector3f p;
    for (int k = 0; k < 3; ++k) p[k] = take<float>(in);
    for (int k = 0; k < 3; ++k) take<float>(in);
    cv::Vec3b rgb;
    for (int k = 0; k < 3; ++k) rgb[k] = take<std::uint8_t>(in);
    out.positions.push_back(p);
    out.colours.push_back(rgb);
  }
  for (std::size_t f = 0; f < faces; ++f) {
    EXPECT_EQ(take<std::uint8_t>(in), 3);
    std::array<int, 3> face;
    for (int c = 0; c < 3; ++c) face[c] = take<std::int32_t>(in);
    EXPECT_EQ(take<std::uint8_t>(in), 6);
    std::array<Eigen::Vector2f, 3> uv;
    for (int c = 0; c < 3; ++c) {
      uv[c].x() = take<float>(in);
      uv[c].y() = take<float>(in);
    }
    out.faces.push_back(face);
    out.face_uvs.push_back(uv);
    out.face_page.push_back(take<std::int32_t>(in));
  }
  EXPECT_TRUE(in.good()) << path << " is shorter than its header says";
  return out;
}

// The read model against the mesh: same triangles at the shifted positions,
// and the texture the reader looks up at each triangle's centre (v up)
// equals the atlas at the mesh's UV.
void expect_same_model(const ReadModel& read, const TexturedMesh& mesh, const std::string& what) {
  std::size_t num_faces = 0;
  for (const auto& indices : mesh.indices) num_faces += indices.size() / 3;
  ASSERT_EQ(read.positions.size(), mesh.positions.size()) << what;
  ASSERT_EQ(read.faces.size(), num_faces) << what;
  ASSERT_EQ(read.pages.size(), mesh.atlases.size()) << what;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    ASSERT_LT((read.positions[v] - (mesh.positions[v] + Eigen::Vector3f(0, 2.5f, 0))).norm(), 1e-5f) << what;
  }
  double error = 0.0;
  std::size_t f = 0, samples = 0;
  for (std::size_t page = 0; page < mesh.indices.size(); ++page) {
    for (std::size_t k = 0; k + 2 < mesh.indices[page].size(); k += 3, ++f) {
      ASSERT_EQ(read.face_page[f], static_cast<int>(page)) << what;
      Eigen::Vector2f expected = Eigen::Vector2f::Zero(), found = Eigen::Vector2f::Zero();
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(read.faces[f][c], static_cast<int>(mesh.indices[page][k + c])) << what;
        expected += mesh.uvs[mesh.indices[page][k + c]] / 3.0f;
        found += Eigen::Vector2f(read.face_uvs[f][c].x(), 1.0f - read.face_uvs[f][c].y()) / 3.0f;
      }
      const Eigen::Vector3f a = testing::sample_atlas(mesh.atlases[page], expected);
      const Eigen::Vector3f b = testing::sample_atlas(read.pages[page], found);
      error += (a - b).cwiseAbs().sum() / 3.0;
      ++samples;
    }
  }
  // JPEG at quality 95 changes smooth 8-bit colours by about one level.
  EXPECT_LT(error / static_cast<double>(samples), 3.0) << what;
}

TEST(ModelWriter, ObjAndPlyReadBackWithTheirTextures) {
  hos::testing::TempDir dir("hos-model-writer");
  const TexturedMesh mesh = shifted_sphere(128);  // several pages
  ASSERT_GT(mesh.atlases.size(), 1u);
  GltfWriteOptions options;
  write_model(dir / "out.obj", mesh, options);
  EXPECT_TRUE(fs::exists(dir / "out.mtl"));
  EXPECT_TRUE(fs::exists(dir / "out_atlas0.jpg"));
  expect_same_model(read_obj(dir / "out.obj"), mesh, "obj");
  options.image_format = "png";
  write_model(dir / "model.PLY", mesh, options);
  const ReadModel ply = read_ply(dir / "model.PLY");
  expect_same_model(ply, mesh, "ply");
  // Vertex colours (PNG: exact): the texel of the face's page under the vertex.
  for (std::size_t f = 0; f < ply.faces.size(); f += 7) {
    const cv::Mat& page = ply.pages[ply.face_page[f]];
    const Eigen::Vector2f& uv = ply.face_uvs[f][0];
    const int x = std::clamp(static_cast<int>(uv.x() * page.cols), 0, page.cols - 1);
    const int y = std::clamp(static_cast<int>((1.0f - uv.y()) * page.rows), 0, page.rows - 1);
    const cv::Vec3b bgr = page.at<cv::Vec3b>(y, x);
    EXPECT_EQ(ply.colours[ply.faces[f][0]], cv::Vec3b(bgr[2], bgr[1], bgr[0])) << "face " << f;
  }
}

TEST(ModelWriter, GltfWithFilesPassesKhronosValidator) {
  hos::testing::TempDir dir("hos-model-writer-gltf");
  const TexturedMesh mesh = shifted_sphere(4096);
  write_model(dir / "scene.gltf", mesh, GltfWriteOptions{});
  EXPECT_TRUE(fs::exists(dir / "scene.bin"));
  EXPECT_TRUE(fs::exists(dir / "scene_atlas0.jpg"));
  const std::string json = hos::testing::read_text(dir / "scene.gltf");
  EXPECT_EQ(json.find("base64"), std::string::npos) << "the buffer must be the .bin file";
  const fs::path modules = hos::testing::bin_dir().parent_path() / "node_tools" / "node_modules";
  if (!fs::exists(modules / "gltf-validator")) GTEST_SKIP() << "gltf-validator is installed by GltfWriter tests";
  const fs::path script = hos::testing::source_dir() / "tests" / "texture" / "validate_gltf.js";
  const int status = hos::testing::run_command("node " + hos::testing::shell_quote(script.string()) + " " +
                                                   hos::testing::shell_quote(modules.string()) + " " +
                                                   hos::testing::shell_quote((dir / "scene.gltf").string()),
                                               dir / "report.json");
  const std::string report = hos::testing::read_text(dir / "report.json");
  EXPECT_EQ(status, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
}

TEST(ModelWriter, GlbConvertsToObjWithTheSameAtlasBytes) {
  hos::testing::TempDir dir("hos-model-convert");
  const TexturedMesh mesh = shifted_sphere(4096);
  write_model(dir / "model.glb", mesh, GltfWriteOptions{});
  const StoredModel stored = read_glb_model(dir / "model.glb");
  ASSERT_EQ(stored.images.size(), mesh.atlases.size());
  convert_model(dir / "model.glb", dir / "copy.obj");
  const std::string jpeg = hos::testing::read_text(dir / "copy_atlas0.jpg");
  EXPECT_EQ(jpeg, std::string(stored.images[0].bytes.begin(), stored.images[0].bytes.end()));
  expect_same_model(read_obj(dir / "copy.obj"), mesh, "converted obj");
}

// A compressed .glb (meshopt over quantized attributes) converts as well:
// every triangle and atlas arrives (the geometry's bounds are
// GltfWriter.EachCompressionReadsBackWithinItsBounds').
TEST(ModelWriter, MeshoptGlbConvertsToObj) {
  hos::testing::TempDir dir("hos-model-convert");
  const TexturedMesh mesh = shifted_sphere(128);
  GltfWriteOptions options;
  options.mesh_compression = "meshopt";
  write_model(dir / "model.glb", mesh, options);
  convert_model(dir / "model.glb", dir / "copy.obj");
  const ReadModel obj = read_obj(dir / "copy.obj");
  std::size_t num_faces = 0;
  for (const auto& page : mesh.indices) num_faces += page.size() / 3;
  EXPECT_EQ(obj.faces.size(), num_faces);
  EXPECT_EQ(obj.pages.size(), mesh.atlases.size());
}

// A .glb converted to .gltf keeps asset.extras: the units and the
// geographic origin of the root frame.
TEST(ModelWriter, GlbConvertsToGltfWithItsPlacement) {
  hos::testing::TempDir dir("hos-model-convert");
  TexturedMesh mesh = shifted_sphere(4096);
  mesh.metric = true;
  mesh.geo_origin = GeoPosition{47.5, 8.25, 412.0};
  write_model(dir / "model.glb", mesh, GltfWriteOptions{});
  convert_model(dir / "model.glb", dir / "copy.gltf");
  const nlohmann::json json = nlohmann::json::parse(hos::testing::read_text(dir / "copy.gltf"));
  const nlohmann::json& extras = json["asset"]["extras"];
  EXPECT_EQ(extras["units"], "metres");
  EXPECT_DOUBLE_EQ(extras["geo_origin"]["latitude_deg"].get<double>(), 47.5);
  EXPECT_DOUBLE_EQ(extras["geo_origin"]["longitude_deg"].get<double>(), 8.25);
  EXPECT_DOUBLE_EQ(extras["geo_origin"]["altitude_m"].get<double>(), 412.0);
  const StoredModel stored = read_glb_model(dir / "model.glb");
  EXPECT_TRUE(stored.mesh.metric);
  ASSERT_TRUE(stored.mesh.geo_origin.has_value());
  EXPECT_EQ(stored.mesh.geo_origin->altitude_m, 412.0);
}

TEST(ModelWriter, UnknownExtensionIsAConfigError) {
  hos::testing::TempDir dir("hos-model-ext");
  EXPECT_TRUE(model_format_of("a.GLTF").has_value());
  EXPECT_FALSE(model_format_of("a.stl").has_value());
  EXPECT_THROW(write_model(dir / "out.stl", shifted_sphere(4096), GltfWriteOptions{}), ConfigError);
}

}  // namespace
}  // namespace hos::texture
