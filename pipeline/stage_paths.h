// Where each stage reads and writes inside the pipeline workspace WS.
#pragma once

#include <filesystem>

namespace hos::pipeline {

struct StagePaths {
  explicit StagePaths(const std::filesystem::path& workspace)
      : root(workspace),
        config(workspace / "config.yaml"),
        run_record(workspace / "run.json"),
        logs(workspace / "logs"),
        sfm(workspace / "sfm"),
        sfm_report(workspace / "sfm" / "report.json"),
        undistorted(workspace / "sfm" / "undistorted"),
        thumbnails(workspace / "sfm" / "thumbnails"),
        points(workspace / "mvs" / "points.ply"),
        mvs_report(workspace / "mvs" / "report.json"),
        depth_maps(workspace / "mvs" / "depth_maps"),
        mesh(workspace / "recon" / "mesh.ply"),
        recon_report(workspace / "recon" / "report.json"),
        recon_tiles(workspace / "recon" / "tiles"),
        refined_mesh(workspace / "refine" / "mesh.ply"),
        textured_model(workspace / "texture" / "model.glb"),
        texture_report(workspace / "texture" / "report.json"),
        view_data(workspace / "texture" / "view_data"),
        eval(workspace / "eval") {}

  std::filesystem::path root;
  std::filesystem::path config;          // resolved config of the last run
  std::filesystem::path run_record;      // run.json
  std::filesystem::path logs;            // logs/<stage>.log
  std::filesystem::path sfm;             // hos-sfm's folder
  std::filesystem::path sfm_report;      // figures of the sfm stage
  std::filesystem::path undistorted;     // sfm output: images + PINHOLE model
  std::filesystem::path thumbnails;      // sfm output: NAME.jpg, small, per usable photo
  std::filesystem::path points;          // mvs output: oriented dense points
  std::filesystem::path mvs_report;      // figures of the mvs stage (coverage, confidence)
  std::filesystem::path depth_maps;      // mvs split runs: the depth maps of the view chunks
  std::filesystem::path mesh;            // recon output: surface
  std::filesystem::path recon_report;    // figures of the recon stage (solver residuals)
  std::filesystem::path recon_tiles;     // recon split runs: the tiles' functions
  std::filesystem::path refined_mesh;    // refine output: the surface the photos agree on
  std::filesystem::path textured_model;  // texture output: binary glTF
  std::filesystem::path texture_report;  // figures of the texture stage (views per face, seams)
  std::filesystem::path view_data;       // texture split runs: the per-view data of the view chunks
  std::filesystem::path eval;            // hos-eval results (--json eval/NAME.json), shown by the report

  std::filesystem::path log(const std::string& stage) const { return logs / (stage + ".log"); }
};

}  // namespace hos::pipeline
