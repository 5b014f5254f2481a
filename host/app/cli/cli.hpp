// The pdmesh command line (CLI11): the top-level app with --version and one subcommand per
// command. Parsing and running are separate so that main() decides how errors become exit codes.
#pragma once
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace CLI {
class App;
}

namespace pdmesh {

struct MeshArguments;
struct QualityArguments;
struct BenchArguments;
struct SmoothArguments;
struct AdaptArguments;

class Cli {
 public:
  Cli();
  ~Cli();
  Cli(const Cli&) = delete;
  Cli& operator=(const Cli&) = delete;

  // Throws CLI::ParseError (including CallForHelp and CallForVersion); main() hands it to app().exit().
  void parse(int argc, const char* const* argv);
  // Runs the subcommand that was parsed. Throws pdmesh errors. Returns the exit status.
  int run();
  CLI::App& app() { return *app_; }

 private:
  std::unique_ptr<CLI::App> app_;
  // Each command: its CLI11 subcommand and what runs it. New commands add one entry.
  std::vector<std::pair<CLI::App*, std::function<int()>>> commands_;
  std::unique_ptr<MeshArguments> mesh_;
  std::unique_ptr<QualityArguments> quality_;
  std::unique_ptr<BenchArguments> bench_;
  std::unique_ptr<SmoothArguments> smooth_;
  std::unique_ptr<AdaptArguments> adapt_;
  bool devices_check_ = false;
};

// The whole command line: parses, runs, and turns typed errors into exit statuses and
// "pdmesh: error: ..." on stderr (bad input 2, other pdmesh errors 1, anything unexpected 1 as an
// internal error). host/main.cpp and the Python console script (python/src/bind_cli.cpp) call it.
int run_command_line(int argc, const char* const* argv);

}  // namespace pdmesh
