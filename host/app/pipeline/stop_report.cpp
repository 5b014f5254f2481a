// The stop message of `pdmesh mesh`; see stop_report.hpp.
#include "app/pipeline/stop_report.hpp"

#include <csignal>
#include <cstdio>
#include <fmt/format.h>

#include "app/pipeline/resume.hpp"

namespace pdmesh {

namespace {

std::string quoted(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789"
                                              "@%_+=:,./-") == std::string::npos)
    return word;
  std::string out = "'";
  for (const char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Whether `word` is `option` or `option=VALUE`; `takes_next` is set for the first form.
bool is_option(const std::string& word, const std::string& option, bool& takes_next) {
  takes_next = word == option;
  return takes_next || word.rfind(option + "=", 0) == 0;
}

}  // namespace

std::string shell_command(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) {
    if (!out.empty()) out += ' ';
    out += quoted(w);
  }
  return out;
}

std::vector<std::string> resume_command(const CaseConfig& config, bool mesh_as_is) {
  const std::vector<std::string>& line = config.command_line;
  if (line.empty()) return {};
  std::vector<std::string> out{line.front()};
  std::vector<std::string> dropped{"--resume", "--stop-after"};
  if (mesh_as_is) dropped.emplace_back("--iterations");
  for (std::size_t i = 1; i < line.size(); ++i) {
    bool takes_next = false, drop = false;
    for (const std::string& option : dropped) drop = drop || is_option(line[i], option, takes_next);
    if (drop) {
      if (takes_next) ++i;
      continue;
    }
    out.push_back(line[i]);
  }
  out.emplace_back("--resume");
  out.push_back(config.out_dir.string());
  if (mesh_as_is) {
    out.emplace_back("--iterations");
    out.emplace_back("0");
  }
  return out;
}

std::string stop_message(const CaseConfig& config, const std::string& phase, int signal,
                         const std::optional<std::string>& saved) {
  const std::string by = signal == SIGINT        ? std::string("SIGINT (Ctrl-C)")
                         : signal == SIGTERM     ? std::string("SIGTERM")
                         : config.stop_after > 0 ? fmt::format("--stop-after {}", config.stop_after)
                                                 : std::string("request");
  const std::string where = phase.empty() ? "while starting" : fmt::format("during {}", phase);
  std::string text = fmt::format("pdmesh: stopped by {} {}", by, where);
  if (!saved) {
    // Nothing new was written: a resumed run's checkpoint is still the one it started from.
    if (config.resume) {
      text += fmt::format("; nothing was written, the checkpoint {} is unchanged\n",
                          checkpoint_path(config.out_dir).string());
    } else {
      text +=
          "; no iteration of the simulation had ended, so there is nothing to continue from: run the same "
          "command again to start over\n";
      return text;
    }
  } else {
    text += fmt::format(", {}\n", *saved);
  }
  const auto go_on = resume_command(config, false), as_is = resume_command(config, true);
  if (go_on.empty()) {
    text +=
        fmt::format("pdmesh: continue with --resume {}; mesh the nodes as they are with --resume {} --iterations 0\n",
                    config.out_dir.string(), config.out_dir.string());
  } else {
    text += fmt::format("pdmesh: to continue the run:           {}\n", shell_command(go_on));
    text += fmt::format("pdmesh: to mesh the nodes as they are: {}\n", shell_command(as_is));
  }
  return text;
}

void report_stop(const CaseConfig& config, const std::string& phase, int signal,
                 const std::optional<std::string>& saved) {
  std::fputs(stop_message(config, phase, signal, saved).c_str(), stderr);
  std::fflush(stderr);
}

}  // namespace pdmesh
