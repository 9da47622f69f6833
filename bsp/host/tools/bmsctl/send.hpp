// bmsctl send: one command of the CAN catalogue to a board over a serial SLCAN port (an L1306 LaunchPad's
// back-channel, or any LAWICEL adapter on the board's CAN bus), and its answer.
//
//   bmsctl send --port DEV [--node N] [--timeout MS] <command> [Signal=value ...]
//
// <command> is a command message of firmware/app/can/bms.yaml by name (ClearFaults, SettingWrite, ...) or
// its kebab-case form (clear-faults, setting-write, ...); the words set its signals as bms-sim's send step
// does (bsp/host/tools/commands/command_frames.hpp): Target = --node (default 1), the alive counter and the
// CRC are filled in. The port is opened raw at 115 200 8N1, the channel opened ("O"), the frame sent as a
// `t` line; the answer (CommandAck, then the command's data frames) is printed one frame per line, and the
// channel closed again ("C"). A repeated counter (the board's last one for that command happened to be the
// same) is retried once with the next counter.
// Exit status: 0 accepted, 1 refused by the board (the reason printed), 2 usage, 3 no answer within the
// timeout (default 1000 ms), 4 the port cannot be opened or configured.
#pragma once

namespace bmsctl {

int runSend(int argc, char** argv);  // argv[0] is the first word after "send"

}  // namespace bmsctl
