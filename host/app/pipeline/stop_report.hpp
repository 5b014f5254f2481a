// What `pdmesh mesh` says when a stop request (Ctrl-C, SIGTERM, --stop-after) ends it: where it
// stopped, what was written, and the whole commands that continue the run and that mesh its nodes
// as they are (the command line it was started with, with --resume DIR added).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"

namespace pdmesh {

// `words` as one shell command line, each word quoted where the shell would split or expand it.
std::string shell_command(const std::vector<std::string>& words);

// The run's command line (config.command_line) without --resume, --stop-after (and, for
// `mesh_as_is`, --iterations), followed by --resume DIR (and --iterations 0). Empty when the
// command line is unknown (a run not started by the command).
std::vector<std::string> resume_command(const CaseConfig& config, bool mesh_as_is);

// The message on stderr (printed also under --quiet): "pdmesh: stopped by SIGINT during PHASE; ..."
// `saved`: what the stop wrote (the checkpoint), when the simulation had run; nullopt: nothing.
std::string stop_message(const CaseConfig& config, const std::string& phase, int signal,
                         const std::optional<std::string>& saved);
void report_stop(const CaseConfig& config, const std::string& phase, int signal,
                 const std::optional<std::string>& saved);

}  // namespace pdmesh
