// glTF 2.0 binary (.glb) files of labelled meshes, through tinygltf.
//
// Layout written: one buffer; one mesh per label present, each with one triangle primitive
// (POSITION float VEC3, NORMAL float VEC3 (flat: each triangle's outward normal), indices uint32,
// custom attribute _PART_ID float SCALAR carrying Mesh::part_ids), material named after the label
// (mesh_label_name: "wall", "door_closed", "glass", "clutter", "floor", "ceiling"; glass is
// translucent); one node per mesh under a root node "building" whose rotation (-90 deg about x)
// turns floorcast's z-up world into glTF's y-up, so standard viewers show the building upright
// (vertex data stay in floorcast's world frame: x, y plan metres, z up); metadata as the scene's
// extras with numbers as JSON numbers.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/sim/mesh.hpp"

namespace floorcast {

/// Writes the mesh as .glb (atomically). `metadata` (a JSON object of strings, numbers, booleans)
/// becomes the scene's extras. Throws InputError on failure.
void save_mesh_glb(const std::string& path, const Mesh& mesh,
                   const nlohmann::json& metadata = nlohmann::json::object());

/// Reads a .glb written by save_mesh_glb (or any glb whose materials are named by label and
/// whose primitives are indexed triangles; node transforms are ignored: vertices are taken in
/// floorcast's world frame). `metadata` receives the scene's extras (strings, numbers, booleans).
/// Throws InputError naming the file and the problem.
Mesh load_mesh_glb(const std::string& path, nlohmann::json* metadata = nullptr);

}  // namespace floorcast
