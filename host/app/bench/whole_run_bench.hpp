// `pdmesh bench --whole-run`: the `mesh` command end to end, each run a separate process (as a user
// runs it), repeated; every phase's wall time from its --timings file, the process's CPU time and
// peak memory from the kernel, min / median / max over the repeats (docs/cli.md, "Whole runs").
#pragma once
#include <string>

#include "app/bench/bench_command.hpp"

namespace pdmesh {

// Runs the whole-run benchmark described by `args` (cases, repeats, backends, extra --set options)
// and prints one Markdown table per case and backend plus a summary; returns the exit status.
int run_whole_run_bench(const BenchArguments& args);

// What a case name stands for: a case directory in `cases_dir` ("30p30n"), "NAME:geometry" (the
// geometry files of that case alone, i.e. pdmesh's best defaults), "annulus_<N>" (generated into
// `work_dir`, app/bench/annulus_case), or any path `pdmesh mesh` accepts (files joined with '+').
std::vector<std::string> whole_run_inputs(const std::string& name, const std::string& cases_dir,
                                          const std::string& work_dir);

}  // namespace pdmesh
