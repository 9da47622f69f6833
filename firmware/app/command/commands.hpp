// What every composition adds for commands (app/monitors/*_app.hpp): the link type its publisher implies, and
// the node number. A composition holds a LimitSettings (before its ProtectionTask, which evaluates the
// settings' limits) and a CommandTask<Link> (after its publisher, whose outbox the link fills), and in
// start() sets the settings as protection's LimitUpdate and starts the command task.
#pragma once

#include <type_traits>

#include "app/command/can_link.hpp"
#include "app/command/command_task.hpp"
#include "app/command/settings.hpp"
#include "app/command/slcan_link.hpp"
#include "app/config.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/slcan_publisher.hpp"
#include "hal/system.hpp"

namespace fw::app::command {

inline constexpr uint8_t kNode = FW_COMMAND_NODE;

template <class Publisher>
using LinkFor = std::conditional_t<std::is_same_v<Publisher, CanPublisher>, CanLink, SlcanLink>;

}  // namespace fw::app::command
