// Tests of node files: exact round trips and FILE:LINE messages for malformed files.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <limits>

#include "core/errors.hpp"
#include "nodes/node_file.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

NodeSet awkward_nodes() {
  NodeSet n;
  n.add({0.0, -0.0}, 0.1, NodeKind::Fixed, 0);
  n.add({1.0 / 3.0, 2.0 / 3.0}, std::nextafter(0.1, 1.0), NodeKind::Boundary, 0);
  n.add({1e-300, -4.9406564584124654e-324}, 1e300, NodeKind::Fixed, 1);
  n.add({std::numeric_limits<double>::max(), -123456789.123456789}, 0.7, NodeKind::Boundary, 1);
  n.add({0.1 + 0.2, M_PI}, std::numeric_limits<double>::min(), NodeKind::Interior, -1);
  n.add({-2.5, 1e22}, 3.0, NodeKind::Interior, -1);
  n.curve_nodes = {{0, 1, 2}, {2, 3, 0}};
  return n;
}

std::string error_of(const std::string& text) {
  try {
    parse_node_file(text, "bad.nodes");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::string kGood =
    "# pdmesh nodes v1\n3\n0 0 fixed 0 1\n1 0 boundary 0 1\n0.5 0.5 interior -1 1\ncurves 1\nc 2 0 1\n";

}  // namespace

TEST_CASE("node files round-trip bit-identically through the file system", "[nodes][app]") {
  const NodeSet n = awkward_nodes();
  const fs::path dir = fs::temp_directory_path() / ("pdmesh_test_nodes_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path path = dir / "initial.nodes";
  write_node_file(path, n, {"upper", "lower"});
  const NodeFile back = read_node_file(path);
  REQUIRE(back.nodes.size() == n.size());
  for (std::size_t i = 0; i < n.size(); ++i) {
    INFO("node " << i);
    CHECK(same_bits(back.nodes.x[i].x, n.x[i].x));
    CHECK(same_bits(back.nodes.x[i].y, n.x[i].y));
    CHECK(same_bits(back.nodes.q[i], n.q[i]));
    CHECK(back.nodes.kind[i] == n.kind[i]);
    CHECK(back.nodes.curve[i] == n.curve[i]);
  }
  CHECK(back.nodes.curve_nodes == n.curve_nodes);
  CHECK(back.curve_names == std::vector<std::string>{"upper", "lower"});
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);  // no temporaries left
  fs::remove_all(dir);
}

TEST_CASE("node file text follows docs/node-file.md", "[nodes][app]") {
  NodeSet n;
  n.add({0, 0}, 0.5, NodeKind::Fixed, 0);
  n.add({1, 0}, 0.25, NodeKind::Fixed, 0);
  n.add({0.5, 0.5}, 1, NodeKind::Interior, 7);  // an interior node is always written with curve -1
  n.curve_nodes = {{0, 1}};
  CHECK(format_node_file(n, {"bottom"}) ==
        "# pdmesh nodes v1\n3\n0 0 fixed 0 0.5\n1 0 fixed 0 0.25\n0.5 0.5 interior -1 1\ncurves 1\nbottom 2 0 1\n");
  CHECK(parse_node_file(kGood, "x").nodes.size() == 3);
  CHECK_THROWS_AS(format_node_file(n, {"has space"}), InputError);
  CHECK_THROWS_AS(format_node_file(n, {}), InputError);
}

TEST_CASE("an empty node set round-trips", "[nodes][app]") {
  const NodeFile f = parse_node_file(format_node_file(NodeSet{}, {}), "empty");
  CHECK(f.nodes.size() == 0);
  CHECK(f.curve_names.empty());
}

TEST_CASE("malformed node files are rejected naming file and line", "[nodes][app]") {
  CHECK(error_of("") == "bad.nodes:1: empty file, expected the header '# pdmesh nodes v1'");
  CHECK(error_of("# pdmesh nodes v2\n0\ncurves 0\n").rfind("bad.nodes:1: expected the header", 0) == 0);
  CHECK(error_of("# pdmesh nodes v1\nthree\n") == "bad.nodes:2: node count 'three' is not an integer");
  CHECK(error_of("# pdmesh nodes v1\n2\n0 0 fixed 0 1\n") ==
        "bad.nodes:2: node count 2 cannot fit in the 14 bytes left in the file (each needs at least 14): the count is "
        "wrong or the file is truncated");
  CHECK(error_of("# pdmesh nodes v1\n2\n0 0 fixed 0 1\n\n\n\n\n\n\n\n\n\n\n\n\n\n") ==
        "bad.nodes:17: unexpected end of file, expected a node line 'x y kind curve q'");
  CHECK(error_of("# pdmesh nodes v1\n1\n0 0 fixed 0\ncurves 0\n") ==
        "bad.nodes:3: expected a node line 'x y kind curve q' (5 fields), got 4 fields");
  CHECK(error_of("# pdmesh nodes v1\n1\n0 nan interior -1 1\ncurves 0\n") == "bad.nodes:3: y 'nan' is not finite");
  CHECK(error_of("# pdmesh nodes v1\n1\n0 1x interior -1 1\ncurves 0\n") == "bad.nodes:3: y '1x' is not a number");
  CHECK(error_of("# pdmesh nodes v1\n1\n0 0 corner 0 1\ncurves 0\n").find("bad.nodes:3: unknown node kind 'corner'") ==
        0);
  CHECK(error_of("# pdmesh nodes v1\n1\n0 0 interior 2 1\ncurves 0\n") ==
        "bad.nodes:3: node 0: an interior node must have curve -1, got 2");
  CHECK(error_of("# pdmesh nodes v1\n1\n0 0 boundary 3 1\ncurves 1\nc 1 0\n") ==
        "bad.nodes:3: node 0 refers to curve 3 but the file has 1 curves");
  // Comments and blank lines are allowed between content lines; line numbers still count them.
  CHECK(error_of("# pdmesh nodes v1\n\n# note\n1\n0 0 fixed 0 1\nnodes 1\n") ==
        "bad.nodes:6: expected 'curves C' after the node lines");
  CHECK(error_of("# pdmesh nodes v1\n1\n0 0 fixed 0 1\ncurves 1\nc 2 0\n") ==
        "bad.nodes:5: curve 'c' declares 2 nodes but lists 1");
  CHECK(error_of("# pdmesh nodes v1\n1\n0 0 fixed 0 1\ncurves 1\nc 1 1\n") ==
        "bad.nodes:5: node index 1 is out of range [0, 0]");
  CHECK(error_of("# pdmesh nodes v1\n2\n0 0 fixed 0 1\n1 1 interior -1 1\ncurves 1\nc 2 0 1\n") ==
        "bad.nodes:6: curve 'c' lists interior node 1");
  CHECK(error_of(kGood + "extra 1\n") == "bad.nodes:8: unexpected content after the last curve line");
  CHECK(error_of("# pdmesh nodes v1\n-1\n") == "bad.nodes:2: node count -1 is out of range [0, 1000000000]");
}

TEST_CASE("the example in docs/node-file.md is a valid node file", "[nodes][app]") {
  std::ifstream in(std::string(PDMESH_SOURCE_DIR) + "/docs/node-file.md");
  std::ostringstream s;
  s << in.rdbuf();
  const std::string doc = s.str();
  const auto start = doc.find("```\n# pdmesh nodes v1\n5");
  REQUIRE(start != std::string::npos);
  const auto end = doc.find("```", start + 3);
  const NodeFile f = parse_node_file(doc.substr(start + 4, end - start - 4), "docs/node-file.md");
  CHECK(f.nodes.size() == 5);
  CHECK(f.curve_names == std::vector<std::string>{"bottom", "right", "top", "left"});
  CHECK(f.nodes.curve_nodes[3] == std::vector<int>{3, 0});
}

TEST_CASE("a missing node file names the path", "[nodes][app]") {
  try {
    read_node_file("/nonexistent/dir/x.nodes");
    FAIL("expected InputError");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("/nonexistent/dir/x.nodes") != std::string::npos);
  }
}
