// The printed quality table (rows of thesis tables 6.2-6.6 plus ours) and quality.json.
// Key names and rows are documented in docs/quality.md.
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "mesh/periodic_links.hpp"
#include "mesh/quality.hpp"

namespace pdmesh {

// One table column per (label, summary), like the thesis' JP Str / JP Ran / PW Del / PW AF.
// Angles get 2 decimals, ratios and the Jacobian 3, as in the thesis.
std::string format_quality_table(const std::vector<std::pair<std::string, QualitySummary>>& columns);
std::string format_quality_table(const QualitySummary& summary, const std::string& label = "mesh");

// The figures of each region (summary.regions) as a table of one row per region, the quality table's
// rows as its columns (the spacing conformance's only when the summary has it), the region's name
// last; empty for fewer than two regions.
std::string format_region_table(const QualitySummary& summary);

// The summary as a JSON document; `source` (e.g. the mesh file) is recorded under "source".
// Non-finite numbers (degenerate triangles) are written as null.
// `healing` (geometry/heal_report.hpp's heal_json) is written as the "healing" object when not empty,
// `periodic` (periodic_json) as the "periodic" array; summary.regions, when not empty, as the
// "regions" array (each entry the top level's figures of the region's triangles). `trailing`:
// further members of the caller's own (a layered mesh's "boundary_layer", a mesh file's "cells"), as
// text that starts with a comma and ends with a line break, appended right after the last member's
// value, before the closing brace.
std::string quality_json(const QualitySummary& summary, const std::string& source = "", const std::string& healing = "",
                         const std::string& periodic = "", const std::string& trailing = "");

// Writes DIR/quality.json (quality_json's text) atomically and returns its path.
std::filesystem::path write_quality_json(const QualitySummary& summary, const std::filesystem::path& dir,
                                         const std::string& source = "", const std::string& healing = "",
                                         const std::string& periodic = "", const std::string& trailing = "");

// quality.json's "periodic" array: per [[periodic]] table its curves (names from `curve_names`), node
// pairs and the largest distance between a source node's transform and its image node; "" without links.
std::string periodic_json(const std::vector<std::string>& curve_names, const std::vector<PeriodicLink>& links);

// A JSON string literal (quotes included) with ", \ and control characters escaped.
std::string json_string(const std::string& text);

}  // namespace pdmesh
