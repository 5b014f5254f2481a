// CPU time as the operating system counts it, in seconds: of the whole process (every thread) and of
// the calling thread.
#pragma once

namespace pdmesh {

double process_cpu_seconds();
double thread_cpu_seconds();

}  // namespace pdmesh
