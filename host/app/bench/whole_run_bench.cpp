// The whole-run benchmark; see whole_run_bench.hpp.
#include "app/bench/whole_run_bench.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/bench/annulus_case.hpp"
#include "app/bench/bench_floor.hpp"
#include "app/config/case_file.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "io/text_file.hpp"
#include "opencl/devices.hpp"

namespace pdmesh {
namespace fs = std::filesystem;
using json = nlohmann::json;
namespace {

struct RunRecord {
  double wall = 0.0, cpu = 0.0;                        // the whole process: wall (fork to exit), user + system
  double peak_rss = 0.0;                               // bytes
  std::vector<std::pair<std::string, double>> phases;  // foreground phases in order: wall
  std::map<std::string, double> phase_cpu;             // their process CPU time
  std::map<std::string, double> notes;                 // iterations, converged, nodes, ...
  std::string backend;                                 // what ran the simulation, as the timings file says
  double pictures = 0.0, picture_cpu = 0.0;            // the background picture jobs, summed: wall, thread CPU
  double load_before = 0.0, load_after = 0.0;
};

double load_average() {
  std::ifstream f("/proc/loadavg");
  double one = 0.0;
  f >> one;
  return one;
}

// A run's timings file (app/pipeline/run_phases.cpp, docs/cli.md "The timings file") into r: every
// numeric top-level member as a note, the backend, the phases (background ones summed as pictures).
void read_timings(const fs::path& timings, RunRecord& r) {
  json t;
  try {
    t = json::parse(read_text_file(timings));
    for (const auto& [key, value] : t.items())
      if (value.is_number()) r.notes[key] = value.get<double>();
    r.backend = t.value("backend", std::string());
    for (const json& p : t.at("phases")) {
      const double wall = p.at("wall").get<double>(), cpu = p.at("cpu").get<double>();
      if (p.at("background").get<bool>()) {
        r.pictures += wall;
        r.picture_cpu += cpu;
      } else {
        const std::string name = p.at("name").get<std::string>();
        r.phases.emplace_back(name, wall);
        r.phase_cpu[name] += cpu;
      }
    }
  } catch (const json::exception& e) {
    throw Error(fmt::format("bench: the timings file '{}' of a run: {}", timings.string(), e.what()));
  }
}

// Runs `pdmesh ARGS...` (this executable) and waits for it; CPU time and peak memory from wait4.
RunRecord run_process(const std::vector<std::string>& args, const fs::path& timings) {
  RunRecord r;
  r.load_before = load_average();
  std::vector<char*> argv;
  std::string self = "/proc/self/exe";
  argv.push_back(self.data());
  std::vector<std::string> copy = args;
  for (std::string& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) throw Error("bench: fork failed");
  if (pid == 0) {
    execv("/proc/self/exe", argv.data());
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  if (wait4(pid, &status, 0, &usage) != pid) throw Error("bench: wait4 failed");
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.load_after = load_average();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw Error(fmt::format("bench: pdmesh {} failed (status {})", fmt::join(args, " "), status));
  r.cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
          1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  r.peak_rss = 1024.0 * static_cast<double>(usage.ru_maxrss);
  read_timings(timings, r);
  return r;
}

struct Spread {
  double min = 0, median = 0, max = 0;
};
Spread spread(std::vector<double> v) {
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  return {v.front(), median, v.back()};
}
std::string seconds(const Spread& s) { return fmt::format("{:.3f} / {:.3f} / {:.3f}", s.min, s.median, s.max); }

// A phase's wall time in a run (its entries summed; 0 when absent).
double phase_wall(const RunRecord& r, const std::string& name) {
  double sum = 0.0;
  for (const auto& [n, w] : r.phases)
    if (n == name) sum += w;
  return sum;
}

// The device of a device-resident run and its precision, from the timings file's backend
// ("opencl:P:D (NAME, TYPE, double, device-resident, ...)", ocl::DeviceSimulator::describe); none for
// every other backend (the host reference, a metric run's host driver over a device's steps).
std::optional<std::pair<ocl::DeviceInfo, ocl::Precision>> run_device(const std::string& backend) {
  static const std::regex resident(R"re(^(opencl:[0-9]+:[0-9]+) \(.*, (double|float), device-resident, )re");
  std::smatch m;
  if (!std::regex_search(backend, m, resident)) return std::nullopt;
  std::optional<ocl::DeviceInfo> info = ocl::select_device(m[1].str());
  if (!info) return std::nullopt;
  return std::make_pair(*info, m[2] == "double" ? ocl::Precision::Double : ocl::Precision::Float);
}

// The summary's simulation cells: wall and CPU ms per iteration (the simulation phase's medians over
// the iterations), the pair-force floor at the run's final node count (wall of both loops, CPU of the
// faster), and the ratios of wall to wall and CPU to CPU. A device-resident run's floor is its device's
// (bench_device_floor: "device T", its kernel ms; the CPU ratio only for a CPU device, whose work is
// the process's CPU time).
std::string simulation_cells(const std::vector<RunRecord>& runs, int floor_repeat) {
  const auto it = runs.front().notes.find("iterations");
  const auto nodes = runs.front().notes.find("nodes");
  if (it == runs.front().notes.end() || it->second < 1) return "- | - | -";
  std::vector<double> sim, sim_cpu;
  for (const RunRecord& r : runs) {
    sim.push_back(phase_wall(r, "simulation"));
    const auto cpu = r.phase_cpu.find("simulation");
    sim_cpu.push_back(cpu == r.phase_cpu.end() ? 0.0 : cpu->second);
  }
  const double per_iteration = spread(sim).median / it->second, cpu_per_iteration = spread(sim_cpu).median / it->second;
  const bool measured = floor_repeat > 0 && nodes != runs.front().notes.end() && nodes->second >= 2;
  if (const auto device = measured ? run_device(runs.front().backend) : std::nullopt) {
    const ocl::DeviceFloorResult* floor =
        bench_device_floor(device->first, device->second, static_cast<std::size_t>(nodes->second), floor_repeat);
    const bool cpu = floor != nullptr && device->first.type == "CPU" && floor->cpu_seconds > 0.0;
    return fmt::format("{:.3f} / {:.3f} | {}; CPU {} | {} / {}", 1e3 * per_iteration, 1e3 * cpu_per_iteration,
                       device_floor_ms_cell(floor), cpu ? fmt::format("{:.3f}", 1e3 * floor->cpu_seconds) : "-",
                       device_floor_ratio_cell(floor, per_iteration),
                       cpu ? fmt::format("{:.2f}", cpu_per_iteration / floor->cpu_seconds) : "-");
  }
  const FloorResult* floor = measured ? &bench_floor(static_cast<std::size_t>(nodes->second), floor_repeat) : nullptr;
  return fmt::format("{:.3f} / {:.3f} | {}; CPU {} | {} / {}", 1e3 * per_iteration, 1e3 * cpu_per_iteration,
                     floor_ms_cell(floor), floor_cpu_ms_cell(floor), floor_ratio_cell(floor, per_iteration),
                     floor_cpu_ratio_cell(floor, cpu_per_iteration));
}

std::string case_table(const std::string& title, const std::vector<RunRecord>& runs) {
  std::string out = fmt::format(
      "\n#### {}\n\n| phase | wall s, min / median / max | CPU s (process, all threads), median |\n|---|---|---|\n",
      title);
  // Phases in the order of the first run; a phase missing from a run counts as absent there.
  for (const auto& [name, unused] : runs.front().phases) {
    (void)unused;
    std::vector<double> v;
    for (const RunRecord& r : runs) v.push_back(phase_wall(r, name));
    std::vector<double> c;
    for (const RunRecord& r : runs) {
      const auto it = r.phase_cpu.find(name);
      c.push_back(it == r.phase_cpu.end() ? 0.0 : it->second);
    }
    out += fmt::format("| {} | {} | {:.3f} |\n", name, seconds(spread(v)), spread(c).median);
  }
  const auto column = [&](auto get) {
    std::vector<double> v;
    for (const RunRecord& r : runs) v.push_back(get(r));
    return spread(v);
  };
  out +=
      fmt::format("| pictures (background thread, overlapping the phases above; CPU of that thread) | {} | {:.3f} |\n",
                  seconds(column([](const RunRecord& r) { return r.pictures; })),
                  column([](const RunRecord& r) { return r.picture_cpu; }).median);
  out += fmt::format("| **whole process** | **{}** | {:.3f} |\n",
                     seconds(column([](const RunRecord& r) { return r.wall; })),
                     column([](const RunRecord& r) { return r.cpu; }).median);
  return out;
}

}  // namespace

std::vector<std::string> whole_run_inputs(const std::string& name, const std::string& cases_dir,
                                          const std::string& work_dir) {
  if (const auto target = annulus_target(name))
    return {write_annulus_case(fs::path(work_dir) / "cases" / name, name, *target).string()};
  const auto colon = name.find(":geometry");
  if (colon != std::string::npos && colon + 9 == name.size()) {
    const CaseConfig config = load_case_file(fs::path(cases_dir) / name.substr(0, colon) / "case.toml");
    std::vector<std::string> files;
    for (const fs::path& f : config.geometry.files) files.push_back(f.string());
    return files;
  }
  if (fs::is_directory(fs::path(cases_dir) / name)) return {(fs::path(cases_dir) / name / "case.toml").string()};
  std::vector<std::string> parts;
  std::stringstream in(name);
  for (std::string p; std::getline(in, p, '+');) parts.push_back(p);
  return parts;
}

int run_whole_run_bench(const BenchArguments& args) {
  if (args.repeat < 1) throw InputError(fmt::format("bench: --repeat must be >= 1, got {}", args.repeat));
  std::string tables;
  std::string summary =
      "| case | backend | nodes | triangles | iterations | wall s, min / median / max | CPU s, median | peak RSS MB, "
      "median | load average before / after | simulation ms/iteration, median: wall / CPU | pair-force floor "
      "ms/iteration at the final nodes: the host CPU's wall scalar / vector; CPU of the faster (a device run: "
      "its device's kernel; CPU on a CPU device) | x floor: wall / CPU "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& name : args.cases) {
    const std::vector<std::string> inputs = whole_run_inputs(name, args.cases_dir, args.work_dir);
    for (const std::string& backend : args.backends) {
      std::vector<RunRecord> runs;
      for (int k = 0; k < args.repeat; ++k) {
        const fs::path out = fs::path(args.work_dir) /
                             fmt::format("{}_{}", fs::path(name).filename().string(), backend) /
                             fmt::format("run{}", k + 1);
        const fs::path timings = out / "timings.json";
        fs::create_directories(out);
        std::vector<std::string> a = {"mesh"};
        a.insert(a.end(), inputs.begin(), inputs.end());
        for (const std::string& s : {std::string("--out"), out.string(), std::string("-q"), std::string("--timings"),
                                     timings.string(), std::string("--device"), backend})
          a.push_back(s);
        if (!args.keep_pictures) a.insert(a.end(), {"--formats", "msh"});
        for (const std::string& s : args.sets) a.insert(a.end(), {"--set", s});
        fmt::print(stderr, "bench: {} on {}, run {} of {}\n", name, backend, k + 1, args.repeat);
        runs.push_back(run_process(a, timings));
      }
      const RunRecord& first = runs.front();
      const auto note = [&](const char* key) {
        const auto it = first.notes.find(key);
        return it == first.notes.end() ? std::string("-") : fmt::format("{:.0f}", it->second);
      };
      std::vector<double> walls, cpus, rss;
      for (const RunRecord& r : runs) {
        walls.push_back(r.wall);
        cpus.push_back(r.cpu);
        rss.push_back(r.peak_rss / 1e6);
      }
      const auto conv = first.notes.find("converged");
      const std::string iterations =
          note("iterations") + (conv != first.notes.end() && conv->second > 0 ? " (converged)" : "");
      summary += fmt::format("| {} | {} | {} | {} | {} | {} | {:.3f} | {:.0f} | {:.1f} / {:.1f} | {} |\n", name,
                             backend, note("nodes"), note("triangles"), iterations, seconds(spread(walls)),
                             spread(cpus).median, spread(rss).median, runs.front().load_before, runs.back().load_after,
                             simulation_cells(runs, args.floor_repeat));
      tables += case_table(fmt::format("{} on {} ({} nodes, {} iterations, {} runs)", name, backend, note("nodes"),
                                       iterations, runs.size()),
                           runs);
      fmt::print("{}", tables.substr(tables.rfind("\n#### ")));
      std::fflush(stdout);
    }
  }
  const std::string all = "### Whole runs\n\n" + summary + tables;
  fmt::print("\n{}", all);
  if (!args.out.empty()) write_file_atomically(args.out, all);
  return 0;
}

}  // namespace pdmesh
