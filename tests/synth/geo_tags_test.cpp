// GPS EXIF and tilted cameras of hos-synth (synth/geo_tags.h, DatasetOptions).
#include "synth/geo_tags.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <exiv2/exiv2.hpp>
#include <filesystem>
#include <numbers>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "synth/dataset.h"
#include "synth/scene.h"

namespace hos::synth {
namespace {

double rational_degrees(const Exiv2::Exifdatum& d) {
  return d.toFloat(0) + d.toFloat(1) / 60.0 + d.toFloat(2) / 3600.0;
}

TEST(GeoTags, SceneAxesAreEastNorthUp) {
  // Scene up is -y, north +z.
  EXPECT_TRUE(enu_from_scene({1, 0, 0}, 2.0).isApprox(Eigen::Vector3d(2, 0, 0)));
  EXPECT_TRUE(enu_from_scene({0, 0, 1}, 2.0).isApprox(Eigen::Vector3d(0, 2, 0)));
  EXPECT_TRUE(enu_from_scene({0, -1, 0}, 2.0).isApprox(Eigen::Vector3d(0, 0, 2)));
}

TEST(GeoTags, WrittenGpsReadsBack) {
  const auto file = std::filesystem::temp_directory_path() / "hos_geo_tags_test.jpg";
  ASSERT_TRUE(cv::imwrite(file.string(), cv::Mat(16, 16, CV_8UC3, cv::Scalar(40, 80, 120))));
  const GeoPosition written{-33.8567844, 151.2152967, -12.25};
  write_gps_exif(file, written);
  auto image = Exiv2::ImageFactory::open(file.string());
  image->readMetadata();
  const Exiv2::ExifData& exif = image->exifData();
  const double latitude = rational_degrees(*exif.findKey(Exiv2::ExifKey("Exif.GPSInfo.GPSLatitude")));
  const double longitude = rational_degrees(*exif.findKey(Exiv2::ExifKey("Exif.GPSInfo.GPSLongitude")));
  EXPECT_EQ(exif.findKey(Exiv2::ExifKey("Exif.GPSInfo.GPSLatitudeRef"))->toString(), "S");
  EXPECT_EQ(exif.findKey(Exiv2::ExifKey("Exif.GPSInfo.GPSLongitudeRef"))->toString(), "E");
  EXPECT_NEAR(latitude, 33.8567844, 1e-9);  // about 0.1 mm
  EXPECT_NEAR(longitude, 151.2152967, 1e-9);
  EXPECT_EQ(exif.findKey(Exiv2::ExifKey("Exif.GPSInfo.GPSAltitudeRef"))->toLong(), 1);
  EXPECT_NEAR(exif.findKey(Exiv2::ExifKey("Exif.GPSInfo.GPSAltitude"))->toFloat(), 12.25, 1e-3);
  std::filesystem::remove(file);
  EXPECT_THROW(write_gps_exif(file, written), OutputError);
}

TEST(GeoTags, TiltTurnsEveryCameraUpOrDown) {
  const Scene scene = make_scene(SceneOptions{});
  DatasetOptions level, tilted;
  tilted.tilt_deg = 15.0;
  const SparseModel a = make_cameras(scene, level), b = make_cameras(scene, tilted);
  const Eigen::Vector3d up(0, -1, 0);
  for (const auto& [id, image] : a.images) {
    const ImageRecord& turned = b.images.at(id);
    EXPECT_LT((turned.center() - image.center()).norm(), 1e-9);
    const double pitch = std::asin(image.viewing_direction().dot(up)) * 180.0 / std::numbers::pi;
    const double turned_pitch = std::asin(turned.viewing_direction().dot(up)) * 180.0 / std::numbers::pi;
    EXPECT_NEAR(turned_pitch - pitch, 15.0, 1e-6);
    // Still level: the x axis stays horizontal.
    EXPECT_NEAR(turned.rotation().row(0).dot(up), 0.0, 1e-9);
  }
  tilted.tilt_deg = 75.0;
  EXPECT_THROW(make_cameras(scene, tilted), ConfigError);
  DatasetOptions gps_png;
  gps_png.gps_origin = GeoPosition{1, 2, 3};
  EXPECT_THROW(gps_png.validate(), ConfigError);
}

}  // namespace
}  // namespace hos::synth
