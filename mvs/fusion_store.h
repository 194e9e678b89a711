// The views fusion reads, under a memory budget. Every view's camera stays
// in memory; its maps and colour stay while the resident ones fit in the
// budget. Beyond it the least recently used are written once to a spill
// folder and read back when a reference view needs them again. Fusion
// checks a view against the views that overlap it most, which a capture
// usually takes one after another, so a spilled view is read back a few
// times at most.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "mvs/fusion.h"
#include "mvs/mvs_options.h"

namespace hos::mvs {

// Bytes that fusion of `views` views of `pixels` each holds at most: the
// used masks of every view, and the maps the store keeps: the budget, or a
// view and its fusion_max_views neighbours when those alone exceed it.
double fusion_peak_bytes(const MvsOptions& options, double pixels, int views);

class FusionViewStore {
 public:
  // budget_bytes 0: no limit (nothing is spilled). The spill folder is made
  // in spill_parent on the first spill and removed with the store; an empty
  // spill_parent is the system's temporary folder (TMPDIR, else /tmp),
  // looked up on the first spill, so an unusable TMPDIR matters only then.
  FusionViewStore(std::size_t budget_bytes, std::filesystem::path spill_parent = {});
  ~FusionViewStore();
  FusionViewStore(const FusionViewStore&) = delete;
  FusionViewStore& operator=(const FusionViewStore&) = delete;

  // Appends a view with its maps; spills others if over the budget. Throws
  // OutputError naming the spill folder's parent (and TMPDIR when it named
  // it) or a spill file that cannot be made or written.
  void add(FusionView view);
  std::size_t size() const { return views_.size(); }

  // Makes the spill folder now (it is made on the first spill otherwise),
  // for a caller that knows the views will not fit: an unusable folder is
  // then named before the work that fills the store. Throws as add.
  void make_spill_folder();

  // Makes the maps of `held` resident and keeps them so until the next call
  // (the budget is exceeded when they alone do not fit). Throws InputError
  // naming a spill file that cannot be read back, OutputError (as add) when
  // one cannot be written.
  void hold(const std::vector<std::size_t>& held);

  // The camera always; the maps and colour only while held (or resident).
  const FusionView& operator[](std::size_t i) const { return views_[i]; }

  // The size of a view's maps, resident or not.
  cv::Size map_size(std::size_t i) const { return {slots_[i].width, slots_[i].height}; }

  std::size_t peak_resident_bytes() const { return peak_bytes_; }
  int spilled_views() const { return spilled_; }
  int maps_read_back() const { return reads_; }

 private:
  struct Slot {
    std::uint64_t last_use = 0;
    bool resident = true, on_disk = false;
    int width = 0, height = 0;
  };
  static std::size_t bytes_of(const Slot& slot);
  std::filesystem::path spill_file(std::size_t i) const;
  void spill(std::size_t i);
  void read_back(std::size_t i);
  void fit_budget(const std::vector<bool>& pinned, std::size_t incoming);

  std::size_t budget_bytes_;
  std::filesystem::path spill_parent_, spill_folder_;
  std::vector<FusionView> views_;
  std::vector<Slot> slots_;
  std::uint64_t clock_ = 0;
  std::size_t resident_bytes_ = 0, peak_bytes_ = 0;
  int spilled_ = 0, reads_ = 0;
};

}  // namespace hos::mvs
