#include "core/geodesy.h"

#include <gtest/gtest.h>

namespace hos {
namespace {

TEST(Geodesy, EcefOfKnownPositions) {
  // On the equator at the prime meridian: the semi-major axis; at the pole: the semi-minor axis.
  EXPECT_NEAR((ecef_from_geodetic({0.0, 0.0, 0.0}) - Eigen::Vector3d(6378137.0, 0, 0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR(ecef_from_geodetic({90.0, 0.0, 0.0}).z(), 6356752.314245, 1e-3);
  EXPECT_NEAR(ecef_from_geodetic({0.0, 90.0, 100.0}).y(), 6378237.0, 1e-6);
}

TEST(Geodesy, EnuRoundTripAndAxes) {
  const EnuFrame frame({46.52, 6.57, 420.0});
  // 100 m east, 200 m north and 30 m up and back, to a millimetre.
  const Eigen::Vector3d enu(100.0, 200.0, 30.0);
  const GeoPosition p = frame.geodetic_from_enu(enu);
  EXPECT_LT((frame.enu_from_geodetic(p) - enu).norm(), 1e-3);
  EXPECT_GT(p.latitude_deg, 46.52);         // north
  EXPECT_GT(p.longitude_deg, 6.57);         // east
  EXPECT_NEAR(*p.altitude_m, 450.0, 0.01);  // the Earth's curvature over 224 m: 4 mm
  // One arc-second of latitude is about 30.9 m here.
  const Eigen::Vector3d north = frame.enu_from_geodetic({46.52 + 1.0 / 3600.0, 6.57, 420.0});
  EXPECT_NEAR(north.y(), 30.9, 0.1);
  EXPECT_NEAR(north.x(), 0.0, 1e-6);
}

}  // namespace
}  // namespace hos
