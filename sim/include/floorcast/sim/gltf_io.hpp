// glTF 2.0 binary (.glb) files of labelled meshes, through tinygltf.
//
// Layout written: one buffer; one mesh per label present, each with one triangle primitive
// (POSITION float VEC3, indices uint32, custom attribute _PART_ID float SCALAR carrying
// Mesh::part_ids), material named after the label (mesh_label_name: "wall", "door_closed",
// "glass", "clutter", "floor", "ceiling"; glass is translucent); one node per mesh with identity
// transform; metadata as string extras of the scene. World frame = floor-plan metres, z up (glTF
// viewers assume y up; rotate if needed).
#pragma once

#include <map>
#include <string>

#include "floorcast/sim/mesh.hpp"

namespace floorcast {

/// Writes the mesh as .glb (atomically). Throws InputError on failure.
void save_mesh_glb(const std::string& path, const Mesh& mesh,
                   const std::map<std::string, std::string>& metadata = {});

/// Reads a .glb written by save_mesh_glb (or any glb whose materials are named by label and
/// whose primitives are indexed triangles; node transforms are ignored). Throws InputError naming
/// the file and the problem.
Mesh load_mesh_glb(const std::string& path, std::map<std::string, std::string>* metadata = nullptr);

}  // namespace floorcast
