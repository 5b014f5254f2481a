// Shared definitions for all pdmesh kernels. The program builder prepends the defines
// REAL (double or float), PDMESH_DOUBLE, WG_SIZE and the capacities, so host and kernels share one set of constants.
#ifndef REAL
#error "REAL must be defined by the program builder"
#endif

// A floating-point literal in REAL: REAL_C(0.5) is 0.5 in double builds and 0.5f in float builds. An
// unsuffixed literal is a double, which a device without cl_khr_fp64 need not accept, even cast.
#if PDMESH_DOUBLE
#define REAL_C(x) x
#else
#define REAL_C(x) x##f
#endif

// Where node i's row starts in a padded neighbour list of `stride` entries per row, in 64 bits: the
// product passes 2^31 long before the node count does (at 2.5M nodes with the stride 856 of shock).
// Every other index (nodes, records, cells) stays below 2^31 for the node counts the host allows.
long row_base(const int i, const int stride) { return (long)i * (long)stride; }
