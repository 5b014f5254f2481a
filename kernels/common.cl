// Shared definitions for all pdmesh kernels. The program builder prepends the defines
// REAL (double or float), WG_SIZE and the capacities, so host and kernels share one set of constants.
#ifndef REAL
#error "REAL must be defined by the program builder"
#endif
