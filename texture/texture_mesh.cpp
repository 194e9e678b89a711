#include "texture/texture_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>

#include "core/error.h"
#include "texture/atlas.h"
#include "texture/charts.h"
#include "texture/decimate.h"
#include "texture/exposure.h"
#include "texture/mesh_topology.h"
#include "texture/seam_leveling.h"
#include "texture/unseen_faces.h"
#include "texture/view_data.h"
#include "texture/view_selection.h"
#include "texture/visibility.h"

namespace hos::texture {

namespace {

class StepTimer {
 public:
  explicit StepTimer(TextureStats& stats) : stats_(stats), start_(Clock::now()) {}
  void lap(const std::string& step) {
    const auto now = Clock::now();
    stats_.step_seconds.emplace_back(step, std::chrono::duration<double>(now - start_).count());
    start_ = now;
  }

 private:
  using Clock = std::chrono::steady_clock;
  TextureStats& stats_;
  Clock::time_point start_;
};

Histogram views_per_face_histogram(const FaceViewCandidates& candidates) {
  std::vector<double> views(static_cast<std::size_t>(candidates.num_faces()));
  for (int f = 0; f < candidates.num_faces(); ++f) views[std::size_t(f)] = candidates.end(f) - candidates.begin(f);
  return make_count_histogram(views, kMaxPlottedViewsPerFace);
}

// The root matrix and how it was found; the identity for up_axis none.
Placement placement_for(const TriangleMesh& mesh,
                        const std::vector<TextureView>& views,
                        const TextureOptions& options,
                        const PlacementInput& input) {
  if (options.up_axis == "none") return {};
  PlacementInput with_options = input;
  if (options.scale_distance != "none") with_options.scale_distance = parse_scale_distance(options.scale_distance);
  return place_model(mesh.vertices, camera_poses(views), with_options);
}

// The mesh texturing works on: the input after validation and (optional)
// decimation, with its topology.
struct PreparedMesh {
  PreparedMesh() = default;
  PreparedMesh(const PreparedMesh&) = delete;  // mesh may point at decimated
  PreparedMesh& operator=(const PreparedMesh&) = delete;

  TriangleMesh decimated;  // empty unless decimation ran
  const TriangleMesh* mesh = nullptr;
  MeshTopology topology;
};

// Checks the mesh and decimates it; what every mode (whole, parts, join)
// does alike, so their meshes are the same.
void prepare_mesh(const TriangleMesh& input_mesh,
                  const std::vector<SamplingCamera>& cameras,
                  const TextureOptions& options,
                  Reporter& reporter,
                  PreparedMesh& prepared,
                  TextureStats& stats,
                  StepTimer& timer) {
  stats.input_faces = input_mesh.faces.size();
  if (input_mesh.faces.empty()) throw StageError("texture", "the mesh has no faces");
  const int num_vertices = static_cast<int>(input_mesh.vertices.size());
  for (std::size_t f = 0; f < input_mesh.faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = input_mesh.faces[f][c];
      if (v < 0 || v >= num_vertices) {
        throw StageError("texture", format_message("mesh face ", f, " refers to vertex ", v, " of ", num_vertices));
      }
    }
  }
  for (const auto& v : input_mesh.vertices) {
    if (!v.allFinite()) throw NumericalError("texture", "the mesh has a non-finite vertex");
  }
  const bool over_budget =
      options.max_faces > 0 && input_mesh.faces.size() > static_cast<std::size_t>(options.max_faces);
  if (over_budget || options.decimation_error_px > 0.0) {
    reporter.begin("decimate", 0);
    const double pixel = options.decimation_error_px > 0.0 ? finest_pixel_size(input_mesh, cameras) : 0.0;
    DecimationStats ds;
    prepared.decimated = decimate_mesh(input_mesh, static_cast<std::size_t>(options.max_faces),
                                       options.decimation_error_px * pixel, &ds);
    reporter.end();
    reporter.info(format_message("decimated ", ds.faces_before, " -> ", ds.faces_after, " faces (error at most ",
                                 options.decimation_error_px, " px of ", pixel, " scene units)"));
    timer.lap("decimate");
  }
  prepared.mesh = prepared.decimated.faces.empty() ? &input_mesh : &prepared.decimated;
  stats.faces = prepared.mesh->faces.size();
  prepared.topology = build_topology(*prepared.mesh);
  timer.lap("topology");
}

// The output's vertices and faces: one vertex per chart vertex, three per
// flat face, each face in its atlas page's index list.
void add_output_vertices(const TriangleMesh& mesh,
                         const MeshTopology& topology,
                         const std::vector<Chart>& charts,
                         const std::vector<FlatFace>& flat,
                         const Atlas& atlas,
                         TexturedMesh& out) {
  out.indices.resize(atlas.pages.size());
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    for (std::size_t i = 0; i < charts[c].vertices.size(); ++i) {
      out.positions.push_back(mesh.vertices[charts[c].vertices[i]]);
      out.normals.push_back(topology.vertex_normals[charts[c].vertices[i]]);
      out.uvs.push_back(atlas.chart_uvs[c][i]);
    }
    auto& indices = out.indices[atlas.chart_page[c]];
    for (const auto& face : charts[c].local_faces) {
      for (int k = 0; k < 3; ++k) indices.push_back(base + static_cast<std::uint32_t>(face[k]));
    }
  }
  for (std::size_t k = 0; k < flat.size(); ++k) {
    auto& indices = out.indices[atlas.flat_page[k]];
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.faces[flat[k].face][c];
      indices.push_back(static_cast<std::uint32_t>(out.positions.size()));
      out.positions.push_back(mesh.vertices[v]);
      out.normals.push_back(topology.vertex_normals[v]);
      out.uvs.push_back(atlas.flat_uvs[k]);
    }
  }
}

// Everything after visibility: exposure, consistency, view selection,
// charts, leveling, atlas and the output mesh.
void texture_from_candidates(const PreparedMesh& prepared,
                             FaceViewCandidates candidates,
                             const std::vector<TextureView>& views,
                             const TextureOptions& options,
                             const PlacementInput& placement,
                             Reporter& reporter,
                             TextureResult& result,
                             StepTimer& timer) {
  const TriangleMesh& mesh = *prepared.mesh;
  const MeshTopology& topology = prepared.topology;
  TextureStats& stats = result.stats;
  stats.num_candidates = static_cast<std::int64_t>(candidates.samples.size());
  stats.views_per_face = views_per_face_histogram(candidates);

  std::vector<Eigen::Vector3f> gains(views.size(), Eigen::Vector3f::Ones());
  if (options.exposure_compensation) {
    gains = estimate_exposure_gains(candidates, static_cast<int>(views.size()), reporter);
    apply_exposure_gains(gains, candidates);
    timer.lap("exposure");
  }
  stats.exposure_gains = gains;
  if (options.outlier_rejection) {
    stats.num_outlier_rejections = reject_outlier_views(candidates, options);
    timer.lap("outliers");
  }
  const ViewSelection selection = select_views(topology, candidates, options, reporter);
  stats.num_unseen_faces = selection.num_unseen;
  timer.lap("view selection");

  std::vector<int> labels = selection.labels;
  stats.num_merged_charts = merge_small_charts(topology, candidates, options.min_chart_area_px, labels);
  const std::vector<Chart> charts = build_charts(mesh, topology, labels);
  stats.num_charts = static_cast<int>(charts.size());
  const SeamLeveling leveling = level_seams(mesh, charts, views, gains, options, reporter);
  stats.num_seam_vertices = leveling.num_seam_vertices;
  stats.mean_seam_jump_before = leveling.mean_seam_jump_before;
  stats.mean_seam_jump_after = leveling.mean_seam_jump_after;
  stats.seam_jumps_before = leveling.seam_jumps_before;
  stats.seam_jumps_after = leveling.seam_jumps_after;
  timer.lap("seam leveling");

  const std::vector<FlatFace> flat = colour_unseen_faces(
      topology, candidates, selection.labels, seen_face_colours(candidates, selection.labels, charts, leveling),
      uniform_backgrounds(views, gains), options.unseen);
  if (!flat.empty()) {
    reporter.warn(format_message(flat.size(), " of ", mesh.faces.size(), " faces are seen by no photo; they take ",
                                 unseen_faces_description(options.unseen)));
  }
  Atlas atlas = build_atlas(mesh, topology, candidates, charts, views, gains, leveling, flat, options, reporter);
  stats.texel_scale = atlas.texel_scale;
  timer.lap("atlas");

  TexturedMesh& out = result.mesh;
  add_output_vertices(mesh, topology, charts, flat, atlas, out);
  out.atlases = std::move(atlas.pages);
  stats.num_atlases = static_cast<int>(out.atlases.size());
  stats.atlas_coverage = atlas_coverage(out);
  for (const auto& page : out.atlases) stats.atlas_sizes.emplace_back(page.cols, page.rows);
  result.placement = placement_for(mesh, views, options, placement);
  out.root_matrix = result.placement.root_matrix;
  out.metric = result.placement.metric;
  out.geo_origin = result.placement.geo_origin;
  stats.estimated_up = result.placement.up.up;
  timer.lap("assemble");
}

ViewDataKey view_data_key(const PreparedMesh& prepared, const TextureView& view, int index, const TextureOptions& o) {
  return {index, static_cast<int>(prepared.mesh->faces.size()), view_data_fingerprint(*prepared.mesh, view, o)};
}

// The candidates of a split run: every view's data, as compute_view_data
// wrote it into folder.
FaceViewCandidates candidates_from_view_data(const PreparedMesh& prepared,
                                             const std::vector<TextureView>& views,
                                             const TextureOptions& options,
                                             const std::filesystem::path& folder,
                                             Reporter& reporter) {
  std::vector<ViewSamples> per_view(views.size());
  reporter.begin("reading view data", static_cast<std::int64_t>(views.size()));
  for (std::size_t v = 0; v < views.size(); ++v) {
    reporter.throw_if_cancelled();
    const int index = static_cast<int>(v);
    per_view[v] =
        read_view_data(view_data_file(folder, views[v].name), view_data_key(prepared, views[v], index, options));
    reporter.advance();
  }
  reporter.end();
  return gather_candidates(static_cast<int>(prepared.mesh->faces.size()), per_view);
}

// A whole texture run from views: the mesh prepared, the candidate views of
// each face found (find_candidates, timed as the step candidates_step:
// visibility, or the per-view data of a split run), then everything after.
template <typename FindCandidates>
TextureResult texture_run(const TriangleMesh& input_mesh,
                          const std::vector<TextureView>& views,
                          const TextureOptions& options,
                          Reporter& reporter,
                          const PlacementInput& placement,
                          const char* candidates_step,
                          FindCandidates find_candidates) {
  TextureResult result;
  StepTimer timer(result.stats);
  result.stats.num_views = static_cast<int>(views.size());
  if (views.empty()) throw StageError("texture", "no registered images to texture from");
  PreparedMesh prepared;
  prepare_mesh(input_mesh, sampling_cameras(views), options, reporter, prepared, result.stats, timer);
  FaceViewCandidates candidates = find_candidates(prepared);
  timer.lap(candidates_step);
  texture_from_candidates(prepared, std::move(candidates), views, options, placement, reporter, result, timer);
  return result;
}

}  // namespace

TextureResult texture_mesh(const TriangleMesh& input_mesh,
                           const std::vector<TextureView>& views,
                           const TextureOptions& options,
                           Reporter& reporter,
                           const PlacementInput& placement) {
  options.validate();
  return texture_run(input_mesh, views, options, reporter, placement, "visibility", [&](const PreparedMesh& prepared) {
    return compute_visibility(*prepared.mesh, prepared.topology, views, options, reporter);
  });
}

TextureResult texture_mesh(const TriangleMesh& mesh,
                           const UndistortedWorkspace& workspace,
                           const TextureOptions& options,
                           Reporter& reporter,
                           const PlacementInput& placement) {
  options.validate();
  const std::vector<TextureView> views = load_texture_views(workspace, reporter);
  return texture_mesh(mesh, views, options, reporter, placement);
}

int compute_view_data(const TriangleMesh& input_mesh,
                      const UndistortedWorkspace& workspace,
                      const TextureOptions& options,
                      Reporter& reporter,
                      const ViewRange& range,
                      const std::filesystem::path& folder) {
  options.validate();
  TextureStats stats;
  StepTimer timer(stats);
  PreparedMesh prepared;
  prepare_mesh(input_mesh, sampling_cameras(workspace.model), options, reporter, prepared, stats, timer);
  const std::vector<TextureView> views = load_texture_views(workspace, reporter, range);
  const int first = std::max(range.first, 0);
  std::filesystem::create_directories(folder);
  const int count = static_cast<int>(views.size());
  std::vector<ViewSamples> per_view(views.size());
  reporter.begin("visibility", count);
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < count; ++i) {
    if (reporter.cancel_requested()) continue;
    per_view[static_cast<std::size_t>(i)] = compute_view_visibility(
        *prepared.mesh, prepared.topology, views[static_cast<std::size_t>(i)], first + i, options);
    reporter.advance();
  }
  reporter.end();
  reporter.throw_if_cancelled();
  // Written outside the parallel loop: a write error must propagate as an exception.
  for (int i = 0; i < count; ++i) {
    const TextureView& view = views[static_cast<std::size_t>(i)];
    write_view_data(view_data_file(folder, view.name), view_data_key(prepared, view, first + i, options),
                    per_view[static_cast<std::size_t>(i)]);
  }
  timer.lap("visibility");
  reporter.info(format_message("texture: view data of views ", range.text(), ": ", count, " of ",
                               workspace.model.images.size(), " views in ", stats.step_seconds.back().second, " s"));
  return count;
}

TextureResult texture_mesh_from_view_data(const TriangleMesh& input_mesh,
                                          const UndistortedWorkspace& workspace,
                                          const TextureOptions& options,
                                          Reporter& reporter,
                                          const std::filesystem::path& folder,
                                          const PlacementInput& placement) {
  options.validate();
  const std::vector<TextureView> views = load_texture_views(workspace, reporter);
  return texture_run(input_mesh, views, options, reporter, placement, "view data", [&](const PreparedMesh& prepared) {
    return candidates_from_view_data(prepared, views, options, folder, reporter);
  });
}

}  // namespace hos::texture
