#include "app/command/identity.hpp"

#include "app/build_id.hpp"  // FW_BUILD_ID (generated when the build was configured)

namespace fw::app::command {

const uint32_t kBuildId = FW_BUILD_ID & 0xFFFFFFU;

}  // namespace fw::app::command
