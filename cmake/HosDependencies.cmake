# Every dependency is a Debian package; scripts/install-deps.sh installs them.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
# video (optical flow) and videoio (FFmpeg) read video clips as photos.
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs video videoio)
find_package(OpenMP REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(Threads REQUIRED)
# COLMAP's database (sfm reads the position priors and matches back).
find_package(SQLite3 REQUIRED)
# Photos' EXIF (libexiv2) and HEIC/HEIF photos (libheif), read and written by sfm.
find_package(PkgConfig REQUIRED)
pkg_check_modules(EXIV2 REQUIRED IMPORTED_TARGET exiv2)
pkg_check_modules(LIBHEIF REQUIRED IMPORTED_TARGET libheif)
find_package(Ceres QUIET)
find_package(CLI11 QUIET)
find_package(GTest QUIET)
find_package(nlohmann_json QUIET)
# Debian's libtinygltf-dev ships the compiled library: never define
# TINYGLTF_IMPLEMENTATION in project code, link TinyGLTF::TinyGLTF.
find_package(TinyGLTF QUIET)
find_package(JPEG REQUIRED)  # JPEG with full chroma (core/jpeg_encoding.h)

# Header-only packages without CMake config files.
find_path(NANOFLANN_INCLUDE_DIR nanoflann.hpp)
find_path(MESHOPTIMIZER_INCLUDE_DIR meshoptimizer.h)
find_library(MESHOPTIMIZER_LIBRARY meshoptimizer)
find_path(MAXFLOW_INCLUDE_DIR maxflow.h PATH_SUFFIXES maxflow-3.0)
find_library(MAXFLOW_LIBRARY maxflow)
