#include "mvs/fusion_store.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include "core/error.h"
#include "mvs/raw_mat_io.h"

namespace hos::mvs {
namespace {

// A view's spilled maps, in this order, as raw rows.
std::vector<cv::Mat*> spilled_mats(FusionView& view) {
  return {&view.map.depth, &view.map.normal, &view.map.cost, &view.color};
}

}  // namespace

double fusion_peak_bytes(const MvsOptions& options, double pixels, int views) {
  const double view_bytes = pixels * fusion_bytes_per_pixel();
  const int held = options.fusion_max_views > 0 ? std::min(views, options.fusion_max_views + 1) : views;
  double maps = views * view_bytes;
  if (options.fusion_memory_mb > 0) {
    maps = std::min(maps, std::max(options.fusion_memory_mb * 1024.0 * 1024.0, held * view_bytes));
  }
  return pixels * views * sizeof(std::uint8_t) + maps;
}

FusionViewStore::FusionViewStore(std::size_t budget_bytes, std::filesystem::path spill_parent)
    : budget_bytes_(budget_bytes), spill_parent_(std::move(spill_parent)) {}

FusionViewStore::~FusionViewStore() {
  if (spill_folder_.empty()) return;
  std::error_code ignored;
  std::filesystem::remove_all(spill_folder_, ignored);
}

std::size_t FusionViewStore::bytes_of(const Slot& slot) {
  return static_cast<std::size_t>(static_cast<double>(slot.width) * slot.height * fusion_bytes_per_pixel());
}

std::filesystem::path FusionViewStore::spill_file(std::size_t i) const {
  return spill_folder_ / (std::to_string(i) + ".fmap");
}

void FusionViewStore::add(FusionView view) {
  Slot slot;
  slot.width = view.map.depth.cols;
  slot.height = view.map.depth.rows;
  slot.last_use = ++clock_;
  views_.push_back(std::move(view));
  slots_.push_back(slot);
  resident_bytes_ += bytes_of(slot);
  fit_budget(std::vector<bool>(views_.size(), false), 0);
}

void FusionViewStore::hold(const std::vector<std::size_t>& held) {
  std::vector<bool> pinned(views_.size(), false);
  std::size_t incoming = 0;
  ++clock_;
  for (std::size_t i : held) {
    if (!pinned[i] && !slots_[i].resident) incoming += bytes_of(slots_[i]);
    pinned[i] = true;
    slots_[i].last_use = clock_;
  }
  // Room first, so that reading the held views back does not raise the peak.
  fit_budget(pinned, incoming);
  for (std::size_t i : held) {
    if (!slots_[i].resident) read_back(i);
  }
}

// Spills the least recently used unpinned views until the resident ones and
// `incoming` bytes fit.
void FusionViewStore::fit_budget(const std::vector<bool>& pinned, std::size_t incoming) {
  while (budget_bytes_ > 0 && resident_bytes_ + incoming > budget_bytes_) {
    std::size_t victim = views_.size();
    for (std::size_t i = 0; i < views_.size(); ++i) {
      if (!slots_[i].resident || pinned[i]) continue;
      if (victim == views_.size() || slots_[i].last_use < slots_[victim].last_use) victim = i;
    }
    if (victim == views_.size()) break;  // only pinned views are resident
    spill(victim);
  }
  peak_bytes_ = std::max(peak_bytes_, resident_bytes_);
}

// A new folder of the store's own (mkdtemp), so that stores never share one.
// The system's temporary folder is looked up only now: a TMPDIR that cannot
// be used costs nothing while every map fits in memory.
void FusionViewStore::make_spill_folder() {
  if (!spill_folder_.empty()) return;
  const char* tmpdir = std::getenv("TMPDIR");
  const bool from_tmpdir = spill_parent_.empty() && tmpdir != nullptr && *tmpdir != '\0';
  const std::filesystem::path parent =
      !spill_parent_.empty() ? spill_parent_ : std::filesystem::path(from_tmpdir ? tmpdir : "/tmp");
  std::string name = (parent / "hos-mvs-fusion-XXXXXX").string();
  if (mkdtemp(name.data()) == nullptr) {
    const std::string reason =
        "cannot make a folder for fusion's spilled depth maps in it: " + std::string(std::strerror(errno));
    if (!from_tmpdir) throw OutputError(parent.string(), reason);
    throw OutputError(parent.string(), reason +
                                           "; the environment variable TMPDIR names this folder: set TMPDIR to a "
                                           "writable folder, or raise mvs.fusion_memory_mb so that nothing spills");
  }
  spill_folder_ = name;
}

// Maps never change once added, so a view is written once however often it
// is dropped.
void FusionViewStore::spill(std::size_t i) {
  Slot& slot = slots_[i];
  FusionView& view = views_[i];
  if (!slot.on_disk) {
    make_spill_folder();
    const auto file = spill_file(i);
    std::ofstream out(file, std::ios::binary);
    for (const cv::Mat* m : spilled_mats(view)) write_raw_mat(out, *m);
    if (!out) throw OutputError(file.string(), "cannot spill fusion's depth maps (disk full?)");
    slot.on_disk = true;
    ++spilled_;
  }
  for (cv::Mat* m : spilled_mats(view)) m->release();
  slot.resident = false;
  resident_bytes_ -= bytes_of(slot);
}

void FusionViewStore::read_back(std::size_t i) {
  Slot& slot = slots_[i];
  FusionView& view = views_[i];
  view.map.depth.create(slot.height, slot.width, CV_32F);
  view.map.normal.create(slot.height, slot.width, CV_16SC2);
  view.map.cost.create(slot.height, slot.width, CV_16F);
  view.color.create(slot.height, slot.width, CV_8UC3);
  const auto file = spill_file(i);
  std::ifstream in(file, std::ios::binary);
  for (cv::Mat* m : spilled_mats(view)) read_raw_mat(in, *m);
  if (!in) throw InputError(file.string(), "cannot read fusion's spilled depth maps back");
  slot.resident = true;
  resident_bytes_ += bytes_of(slot);
  peak_bytes_ = std::max(peak_bytes_, resident_bytes_);
  ++reads_;
}

}  // namespace hos::mvs
