// Reading COLMAP's database back: position priors and verified matches.
#include "sfm/colmap_database.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {

// The tables and columns of COLMAP 3.8's database that the stage reads.
void make_database(const std::filesystem::path& file, const std::string& rows) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
  const std::string sql =
      "CREATE TABLE images (image_id INTEGER PRIMARY KEY, name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL, "
      "prior_qw REAL, prior_qx REAL, prior_qy REAL, prior_qz REAL, prior_tx REAL, prior_ty REAL, prior_tz REAL);"
      "CREATE TABLE two_view_geometries (pair_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, "
      "cols INTEGER NOT NULL, data BLOB, config INTEGER NOT NULL);" +
      rows;
  char* error = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK) << (error ? error : "");
  sqlite3_free(error);
  sqlite3_close(db);
}

// COLMAP's pair id of images a < b.
long long pair_id(long long a, long long b) { return a * 2147483647LL + b; }

TEST(ColmapDatabase, ReadsPositionPriorsAndMissingOnes) {
  hos::testing::TempDir dir;
  make_database(dir / "database.db",
                "INSERT INTO images VALUES (1, 'DCIM/a.jpg', 1, NULL, NULL, NULL, NULL, 46.52, 6.63, 0.0);"
                "INSERT INTO images VALUES (2, 'b.jpg', 1, NULL, NULL, NULL, NULL, NULL, NULL, NULL);");
  const auto images = read_database_images(dir / "database.db");
  ASSERT_EQ(images.size(), 2u);
  EXPECT_EQ(images[0].name, "DCIM/a.jpg");
  ASSERT_TRUE(images[0].position_prior.has_value());
  EXPECT_DOUBLE_EQ((*images[0].position_prior)[0], 46.52);
  EXPECT_DOUBLE_EQ((*images[0].position_prior)[1], 6.63);
  EXPECT_FALSE(images[1].position_prior.has_value());
}

TEST(ColmapDatabase, BestVerifiedMatchesPerImage) {
  hos::testing::TempDir dir;
  make_database(dir / "database.db",
                "INSERT INTO images (image_id, name, camera_id) VALUES (1, 'a.jpg', 1), (2, 'b.jpg', 1), "
                "(3, 'c.jpg', 1), (4, 'lone.jpg', 2);"
                "INSERT INTO two_view_geometries VALUES (" +
                    std::to_string(pair_id(1, 2)) + ", 120, 2, NULL, 2), (" + std::to_string(pair_id(1, 3)) +
                    ", 40, 2, NULL, 2), (" + std::to_string(pair_id(3, 4)) + ", 9, 2, NULL, 2);");
  const auto best = best_verified_matches(dir / "database.db");
  EXPECT_EQ(best.at("a.jpg"), 120);
  EXPECT_EQ(best.at("b.jpg"), 120);
  EXPECT_EQ(best.at("c.jpg"), 40);
  EXPECT_EQ(best.at("lone.jpg"), 9);
}

TEST(ColmapDatabase, UnreadableDatabaseIsAStageError) {
  hos::testing::TempDir dir;
  EXPECT_THROW(read_database_images(dir / "none.db"), StageError);
}

}  // namespace
}  // namespace hos::sfm
