// Names of node kinds, as written to node files and pictures.
#include "nodes/node_set.hpp"

namespace pdmesh {

const char* to_string(NodeKind kind) {
  switch (kind) {
    case NodeKind::Fixed:
      return "fixed";
    case NodeKind::Boundary:
      return "boundary";
    case NodeKind::Interior:
      return "interior";
  }
  return "?";
}

}  // namespace pdmesh
