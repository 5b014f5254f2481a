// A file against the layer order inside app/, for test layer_order_catches_upward_in_app: the case
// configuration includes the pipeline above it.
#pragma once
#include "app/pipeline/run_phases.hpp"
