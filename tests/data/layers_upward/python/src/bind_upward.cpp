// A binding file that includes the command-line layer, for test layer_order_catches_binding_on_cli
// (only bind_cli.cpp may: its job is to run the command line).
#include "bindings.hpp"
#include "app/cli/cli.hpp"
