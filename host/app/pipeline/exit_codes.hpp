// Exit statuses of the pdmesh command (README "When things go wrong").
#pragma once

namespace pdmesh {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;        // device, simulation or internal failure
inline constexpr int kExitInput = 2;          // bad input: command line, case file, geometry, limits
inline constexpr int kExitInterrupted = 130;  // SIGINT/SIGTERM: stopped, checkpoint and outputs written

}  // namespace pdmesh
