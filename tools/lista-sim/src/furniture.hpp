// Real furniture: the Sweet Home 3D catalogues of Debian's
// sweethome3d-furniture (unpacked by tools/fetch-shapes.sh), OBJ meshes with
// y up and polygon faces, sized by the catalogue's width x depth x height.
// Used by `lista-sim views --furniture DIR` so descriptors train and are
// benchmarked on shapes no procedural generator made.
#pragma once

#include "shapes.hpp"

#include <Eigen/Core>
#include <string>
#include <vector>

namespace lista::sim {

// One catalogue entry (keys `id#N`, `name#N`, `category#N`, `model#N`,
// `width#N`, `depth#N`, `height#N` in cm, `modelRotation#N`, `doorOrWindow#N`,
// `staircaseCutOutShape#N` of a PluginFurnitureCatalog.properties file).
struct CatalogEntry {
  std::string id, name, category;
  std::string model;  // absolute path of the OBJ file
  Eigen::Vector3f size_cm = Eigen::Vector3f::Zero();  // width, depth, height
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();  // modelRotation, row-major in the file
  bool door_or_window = false, staircase = false;
};

// Entries of one .properties catalogue in index order; model paths are made
// absolute against the catalogue's folder. Throws lista::Error naming the
// file and line for an unreadable file or a malformed number.
std::vector<CatalogEntry> read_catalog(const std::string& properties_path);

// An OBJ file's vertices and faces (v and f records; polygons fanned into
// triangles; negative indices count back from the last vertex; everything
// else ignored; two-vertex faces have no area and are dropped). Throws
// lista::Error naming the file and line.
TriMesh read_obj(const std::string& path);

// The entry as a lista-sim shape: rotated by modelRotation, turned from y up
// to z up (x stays, SH3D depth becomes y), scaled so its box is the
// catalogue's size, standing on z = 0 (normalise_shape).
Shape furniture_shape(const CatalogEntry& entry);

// Every usable entry of every catalogue under `folder` (searched
// recursively, in sorted path order): doors, windows, staircases and people
// are left out, and so is what a change detector would not cut out as an
// object of its own (under 20 cm tall and wide, e.g. a vase) or could not
// stand in a room (over 3 m tall, a footprint side over 6 m). Entries whose
// model fails to load are skipped and named in `skipped` when given.
// Throws lista::Error when the folder holds no catalogue.
std::vector<Shape> load_furniture(const std::string& folder, std::vector<std::string>* skipped = nullptr);

}  // namespace lista::sim
