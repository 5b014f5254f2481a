// Shapefile reader (shapefile_reader.hpp) on shapelib's SHP and DBF API.
#include "geometry/shapefile_reader.hpp"

#include <cmath>
#include <filesystem>
#include <memory>

#include <fmt/format.h>
#include <shapefil.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "core/progress_notes.hpp"
#include "geometry/gis_features.hpp"

namespace pdmesh {

namespace {

constexpr double kLargestCoordinate = 1e150;  // as for the text readers (reader_text.cpp)

// shapelib reports through its hooks' Error(); the last message is kept for ours.
thread_local std::string last_shapelib_error;
void keep_error(const char* message) {
  last_shapelib_error = message != nullptr ? message : "";
  // shapelib's hint about a configuration option of GDAL's, which pdmesh does not have.
  const std::size_t hint = last_shapelib_error.find(" Set SHAPE_RESTORE_SHX");
  if (hint != std::string::npos) last_shapelib_error.resize(hint);
}

SAHooks hooks() {
  SAHooks h;
  SASetupDefaultHooks(&h);
  h.Error = keep_error;
  return h;
}

struct ShpCloser {
  void operator()(SHPInfo* h) const { SHPClose(h); }
};
struct DbfCloser {
  void operator()(DBFInfo* h) const { DBFClose(h); }
};
struct ObjectDestroyer {
  void operator()(SHPObject* o) const { SHPDestroyObject(o); }
};

// Twice the signed area (> 0 counter-clockwise).
double signed_area2(const std::vector<Vec2>& ring) {
  double a = 0.0;
  for (std::size_t k = 0; k + 1 < ring.size(); ++k) a += ring[k].x * ring[k + 1].y - ring[k].y * ring[k + 1].x;
  if (!ring.empty()) a += ring.back().x * ring.front().y - ring.back().y * ring.front().x;
  return a;
}

const char* shape_kind(int type) {
  switch (type) {
    case SHPT_POINT:
    case SHPT_POINTZ:
    case SHPT_POINTM:
    case SHPT_MULTIPOINT:
    case SHPT_MULTIPOINTZ:
    case SHPT_MULTIPOINTM:
      return "point";
    case SHPT_ARC:
    case SHPT_ARCZ:
    case SHPT_ARCM:
      return "line";
    case SHPT_POLYGON:
    case SHPT_POLYGONZ:
    case SHPT_POLYGONM:
      return "polygon";
    default:
      return nullptr;
  }
}

}  // namespace

RawGeometry read_shapefile(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    // read_input_file says why (missing, a directory, a device ...) in the usual words.
    read_input_file(path, InputKind::Geometry);
  }
  SAHooks h = hooks();
  last_shapelib_error.clear();
  std::unique_ptr<SHPInfo, ShpCloser> shp(SHPOpenLL(path.c_str(), "rb", &h));
  if (!shp) {
    throw InputError(fmt::format("{}: cannot read the shapefile: {} (a shapefile needs its .shx index beside it)", path,
                                 last_shapelib_error.empty() ? "shapelib cannot open it" : last_shapelib_error));
  }
  int count = 0, type = 0;
  double lo[4], hi[4];
  SHPGetInfo(shp.get(), &count, &type, lo, hi);
  if (shape_kind(type) == nullptr) {
    throw InputError(
        fmt::format("{}: shape type {} ({}) is not supported (Point, MultiPoint, PolyLine, Polygon and "
                    "their Z and M variants are)",
                    path, type, SHPTypeName(type)));
  }
  // The .dbf beside it, for names; without one the curves are unnamed.
  const std::string dbf_path = std::filesystem::path(path).replace_extension(".dbf").string();
  std::unique_ptr<DBFInfo, DbfCloser> dbf;
  int name_field = -1;
  if (std::filesystem::is_regular_file(dbf_path)) {
    dbf.reset(DBFOpenLL(dbf_path.c_str(), "rb", &h));
    if (dbf) name_field = DBFGetFieldIndex(dbf.get(), "name");
  }

  RawGeometry out;
  for (int i = 0; i < count; ++i) {
    std::unique_ptr<SHPObject, ObjectDestroyer> obj(SHPReadObject(shp.get(), i));
    if (!obj) {
      throw InputError(
          fmt::format("{}:{}: record {} cannot be read: {}", path, i + 1, i + 1,
                      last_shapelib_error.empty() ? "the file is truncated or corrupt" : last_shapelib_error));
    }
    if (obj->nSHPType == SHPT_NULL) {
      progress_line(fmt::format("geometry: {}:{}: record {} has no shape (Null); skipped", path, i + 1, i + 1));
      continue;
    }
    gis::FeatureSource src{path, i + 1, "", fmt::format("record {}", i + 1)};
    if (name_field >= 0 && i < DBFGetRecordCount(dbf.get()) && !DBFIsAttributeNULL(dbf.get(), i, name_field)) {
      const std::string name = DBFReadStringAttribute(dbf.get(), i, name_field);
      if (!name.empty()) {
        src.name = gis::plain_name(name);
        src.what = fmt::format("record {} ('{}')", i + 1, quote_input(name));
      }
    }
    const int n = obj->nVertices;
    for (int k = 0; k < n; ++k) {
      if (!(std::fabs(obj->padfX[k]) <= kLargestCoordinate && std::fabs(obj->padfY[k]) <= kLargestCoordinate)) {
        throw InputError(
            fmt::format("{}:{}: {}: vertex {} ({}, {}) is not finite or too large (|value| must be <= "
                        "{:g})",
                        path, i + 1, src.what, k, obj->padfX[k], obj->padfY[k], kLargestCoordinate));
      }
    }
    auto part = [&](int p) {
      const int from = obj->nParts > 0 ? obj->panPartStart[p] : 0;
      const int to = p + 1 < obj->nParts ? obj->panPartStart[p + 1] : n;
      std::vector<Vec2> pts;
      for (int k = from; k < to; ++k) pts.push_back({obj->padfX[k], obj->padfY[k]});
      return pts;
    };
    const std::string kind = shape_kind(obj->nSHPType) != nullptr ? shape_kind(obj->nSHPType) : "";
    if (kind == "point") {
      for (int k = 0; k < n; ++k) gis::add_point(out, src, {obj->padfX[k], obj->padfY[k]});
    } else if (kind == "line") {
      for (int p = 0; p < obj->nParts; ++p) gis::add_line(out, src, obj->nParts > 1 ? p + 1 : 0, part(p));
    } else if (kind == "polygon") {
      // The format's rule: outer rings run clockwise, holes counter-clockwise after their outer ring.
      std::vector<std::vector<std::vector<Vec2>>> polygons;
      for (int p = 0; p < obj->nParts; ++p) {
        std::vector<Vec2> ring = part(p);
        if (polygons.empty() || signed_area2(ring) < 0.0) polygons.emplace_back();
        polygons.back().push_back(std::move(ring));
      }
      for (std::size_t k = 0; k < polygons.size(); ++k)
        gis::add_polygon(out, src, polygons.size() > 1 ? static_cast<int>(k + 1) : 0, std::move(polygons[k]));
    } else {
      throw InputError(fmt::format("{}:{}: {}: shape type {} ({}) is not supported", path, i + 1, src.what,
                                   obj->nSHPType, SHPTypeName(obj->nSHPType)));
    }
  }
  gis::finish(out, path, 0, 0);
  return out;
}

}  // namespace pdmesh
