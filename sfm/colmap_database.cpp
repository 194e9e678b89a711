#include "sfm/colmap_database.h"

#include <sqlite3.h>

#include <algorithm>
#include <cstdint>
#include <memory>

#include "core/error.h"

namespace hos::sfm {
namespace {

// COLMAP 3.8 packs an image pair into one id (database.h).
constexpr std::int64_t kMaxImageId = 2147483647;

class Database {
 public:
  explicit Database(const std::filesystem::path& file) : file_(file) {
    sqlite3* db = nullptr;
    const int rc = sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
    db_.reset(db);
    if (rc != SQLITE_OK) fail("cannot open");
  }

  // Calls row(statement) for each row of the query.
  template <typename Row>
  void each_row(const char* sql, Row&& row) {
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db_.get(), sql, -1, &raw, nullptr) != SQLITE_OK) fail("cannot query");
    const std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)> statement(raw, &sqlite3_finalize);
    int rc = SQLITE_ROW;
    while ((rc = sqlite3_step(raw)) == SQLITE_ROW) row(raw);
    if (rc != SQLITE_DONE) fail("cannot read");
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw StageError("sfm", what + " COLMAP's database " + file_.string() + ": " +
                                (db_ ? sqlite3_errmsg(db_.get()) : "out of memory"));
  }

  std::filesystem::path file_;
  std::unique_ptr<sqlite3, decltype(&sqlite3_close)> db_{nullptr, &sqlite3_close};
};

std::string text_column(sqlite3_stmt* statement, int column) {
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(statement, column));
  return text ? std::string(text, static_cast<std::size_t>(sqlite3_column_bytes(statement, column))) : std::string();
}

}  // namespace

std::vector<DatabaseImage> read_database_images(const std::filesystem::path& database) {
  Database db(database);
  std::vector<DatabaseImage> images;
  db.each_row("SELECT image_id, name, camera_id, prior_tx, prior_ty, prior_tz FROM images ORDER BY image_id",
              [&](sqlite3_stmt* row) {
                DatabaseImage image;
                image.id = sqlite3_column_int(row, 0);
                image.name = text_column(row, 1);
                image.camera_id = sqlite3_column_int(row, 2);
                // SQLite stores COLMAP's NaN (no prior) as NULL.
                bool present = true;
                for (int column = 3; column <= 5; ++column) {
                  present = present && sqlite3_column_type(row, column) != SQLITE_NULL;
                }
                if (present) {
                  image.position_prior = std::array<double, 3>{
                      sqlite3_column_double(row, 3), sqlite3_column_double(row, 4), sqlite3_column_double(row, 5)};
                }
                images.push_back(std::move(image));
              });
  return images;
}

std::map<std::string, int> best_verified_matches(const std::filesystem::path& database) {
  std::map<int, std::string> names;
  std::map<std::string, int> best;
  for (const DatabaseImage& image : read_database_images(database)) {
    names[image.id] = image.name;
    best[image.name] = 0;
  }
  Database db(database);
  db.each_row("SELECT pair_id, rows FROM two_view_geometries", [&](sqlite3_stmt* row) {
    const std::int64_t pair = sqlite3_column_int64(row, 0);
    const int inliers = sqlite3_column_int(row, 1);
    for (const std::int64_t id : {pair / kMaxImageId, pair % kMaxImageId}) {
      const auto name = names.find(static_cast<int>(id));
      if (name != names.end()) best[name->second] = std::max(best[name->second], inliers);
    }
  });
  return best;
}

}  // namespace hos::sfm
