#include "pipeline/driver/stage_config.h"

#include "pipeline/sfm/sfm_options.h"

// Stage libraries are optional parts of a build (HOS_MODULES); CMake defines
// HOS_DRIVER_WITH_<STAGE> for those that are built.
#if HOS_DRIVER_WITH_MVS
#include "mvs/mvs_options.h"
#endif
#if HOS_DRIVER_WITH_RECON
#include "recon/recon_options.h"
#endif
#if HOS_DRIVER_WITH_TEXTURE
#include "texture/texture_options.h"
#endif

namespace hos {

const std::vector<std::string>& pipeline_stage_names() {
  static const std::vector<std::string> kStages{"sfm", "mvs", "recon", "texture"};
  return kStages;
}

std::unique_ptr<StageConfig> make_stage_config(const std::string& stage) {
  if (stage == "sfm") return std::make_unique<TypedStageConfig<SfmOptions>>(stage);
#if HOS_DRIVER_WITH_MVS
  if (stage == "mvs") return std::make_unique<TypedStageConfig<MvsOptions>>(stage);
#endif
#if HOS_DRIVER_WITH_RECON
  if (stage == "recon") return std::make_unique<TypedStageConfig<ReconOptions>>(stage);
#endif
#if HOS_DRIVER_WITH_TEXTURE
  if (stage == "texture") return std::make_unique<TypedStageConfig<TextureOptions>>(stage);
#endif
  return nullptr;
}

}  // namespace hos
