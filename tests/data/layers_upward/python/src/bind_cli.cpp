// The one binding file that may include the command-line layer (check_layers.cmake, PYTHON_CLI_FILES).
#include "app/cli/cli.hpp"
