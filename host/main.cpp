// The pdmesh command. Parses the command line (CLI11) and turns typed errors into exit codes.
#include <cstdio>

int main() {
  std::puts("pdmesh: under construction");
  return 0;
}
