#include "floorcast/sim/gltf_io.hpp"

#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "floorcast/floorplans/io.hpp"

namespace floorcast {
namespace {

/// Display colour (RGBA) per label.
std::array<double, 4> label_color(MeshLabel l) {
  switch (l) {
    case MeshLabel::kWall: return {0.85, 0.85, 0.82, 1.0};
    case MeshLabel::kDoorClosed: return {0.55, 0.35, 0.20, 1.0};
    case MeshLabel::kGlass: return {0.55, 0.75, 0.90, 0.3};
    case MeshLabel::kClutter: return {0.30, 0.45, 0.65, 1.0};
    case MeshLabel::kFloor: return {0.60, 0.58, 0.55, 1.0};
    case MeshLabel::kCeiling: return {0.95, 0.95, 0.95, 1.0};
  }
  return {1.0, 0.0, 1.0, 1.0};
}

template <typename T>
std::size_t append(std::vector<unsigned char>& buf, const std::vector<T>& values) {
  while (buf.size() % 4) buf.push_back(0);
  const std::size_t offset = buf.size();
  buf.resize(offset + values.size() * sizeof(T));
  std::memcpy(buf.data() + offset, values.data(), values.size() * sizeof(T));
  return offset;
}

int add_view_accessor(tinygltf::Model& model, std::size_t offset, std::size_t bytes, int target, int component,
                      std::size_t count, int type) {
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = offset;
  view.byteLength = bytes;
  view.target = target;
  model.bufferViews.push_back(view);
  tinygltf::Accessor acc;
  acc.bufferView = static_cast<int>(model.bufferViews.size() - 1);
  acc.byteOffset = 0;
  acc.componentType = component;
  acc.count = count;
  acc.type = type;
  model.accessors.push_back(acc);
  return static_cast<int>(model.accessors.size() - 1);
}

/// Reads element i of an accessor as doubles (ncomp components).
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, int index, const std::string& path, const std::string& what)
      : path_(path), what_(what) {
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) fail("accessor index out of range");
    acc_ = &model.accessors[static_cast<std::size_t>(index)];
    if (acc_->bufferView < 0 || static_cast<std::size_t>(acc_->bufferView) >= model.bufferViews.size()) {
      fail("accessor without a valid buffer view");
    }
    const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(acc_->bufferView)];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) fail("bad buffer index");
    const tinygltf::Buffer& buf = model.buffers[static_cast<std::size_t>(view.buffer)];
    comp_size_ = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(acc_->componentType));
    ncomp_ = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc_->type));
    if (comp_size_ <= 0 || ncomp_ <= 0) fail("unsupported accessor type");
    const int stride = acc_->ByteStride(view);
    if (stride <= 0) fail("invalid byte stride");
    stride_ = static_cast<std::size_t>(stride);
    const std::size_t begin = view.byteOffset + acc_->byteOffset;
    const std::size_t need = acc_->count == 0 ? 0 : (acc_->count - 1) * stride_ + comp_size_ * ncomp_;
    if (begin + need > buf.data.size() || acc_->byteOffset + need > view.byteLength) fail("data past the end of its buffer");
    data_ = buf.data.data() + begin;
  }
  std::size_t count() const { return acc_->count; }
  int components() const { return ncomp_; }
  int component_type() const { return acc_->componentType; }
  double get(std::size_t i, int c) const {
    const unsigned char* p = data_ + i * stride_ + static_cast<std::size_t>(c * comp_size_);
    switch (acc_->componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t u;
        std::memcpy(&u, p, 4);
        return u;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t u;
        std::memcpy(&u, p, 2);
        return u;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
      default: fail("unsupported component type " + std::to_string(acc_->componentType));
    }
  }

 private:
  [[noreturn]] void fail(const std::string& why) const { throw InputError(path_ + ": " + what_ + ": " + why); }
  std::string path_, what_;
  const tinygltf::Accessor* acc_ = nullptr;
  const unsigned char* data_ = nullptr;
  std::size_t stride_ = 0;
  int comp_size_ = 0, ncomp_ = 0;
};

}  // namespace

void save_mesh_glb(const std::string& path, const Mesh& mesh, const nlohmann::json& metadata) {
  if (mesh.labels.size() != mesh.triangles.size() || mesh.part_ids.size() != mesh.triangles.size()) {
    throw InputError(path + ": mesh labels/part ids do not match its triangles");
  }
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "floorcast";
  model.buffers.emplace_back();
  std::vector<unsigned char>& buf = model.buffers[0].data;
  tinygltf::Scene scene;
  scene.name = "building";
  std::vector<int> children;

  for (int li = 0; li < kNumMeshLabels; ++li) {
    const MeshLabel label = static_cast<MeshLabel>(li);
    std::vector<float> pos;
    std::vector<float> nrm;
    std::vector<float> part;
    std::vector<std::uint32_t> idx;
    std::array<float, 3> lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::max()};
    std::array<float, 3> hi{-lo[0], -lo[1], -lo[2]};
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.labels[t] != label) continue;
      Eigen::Vector3f n = mesh.normal(t);
      if (!n.allFinite() || n.norm() < 0.5f) n = Eigen::Vector3f::UnitZ();  // degenerate: any unit normal
      for (int k = 0; k < 3; ++k) {
        nrm.insert(nrm.end(), {n.x(), n.y(), n.z()});
        const Eigen::Vector3f& v = mesh.vertices_m[static_cast<std::size_t>(mesh.triangles[t][k])];
        for (int c = 0; c < 3; ++c) {
          pos.push_back(v[c]);
          lo[static_cast<std::size_t>(c)] = std::min(lo[static_cast<std::size_t>(c)], v[c]);
          hi[static_cast<std::size_t>(c)] = std::max(hi[static_cast<std::size_t>(c)], v[c]);
        }
        part.push_back(static_cast<float>(mesh.part_ids[t]));
        idx.push_back(static_cast<std::uint32_t>(idx.size()));
      }
    }
    if (idx.empty()) continue;
    const std::size_t nv = pos.size() / 3;
    const int a_pos = add_view_accessor(model, append(buf, pos), pos.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER,
                                        TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
    model.accessors[static_cast<std::size_t>(a_pos)].minValues = {lo[0], lo[1], lo[2]};
    model.accessors[static_cast<std::size_t>(a_pos)].maxValues = {hi[0], hi[1], hi[2]};
    const int a_nrm = add_view_accessor(model, append(buf, nrm), nrm.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER,
                                        TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
    const int a_part = add_view_accessor(model, append(buf, part), part.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER,
                                         TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_SCALAR);
    const int a_idx = add_view_accessor(model, append(buf, idx), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER,
                                        TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, idx.size(), TINYGLTF_TYPE_SCALAR);
    tinygltf::Material mat;
    mat.name = mesh_label_name(label);
    const auto color = label_color(label);
    mat.pbrMetallicRoughness.baseColorFactor = {color[0], color[1], color[2], color[3]};
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    mat.pbrMetallicRoughness.roughnessFactor = label == MeshLabel::kGlass ? 0.05 : 0.9;
    mat.doubleSided = true;
    if (color[3] < 1.0) mat.alphaMode = "BLEND";
    model.materials.push_back(mat);
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = a_pos;
    prim.attributes["NORMAL"] = a_nrm;
    prim.attributes["_PART_ID"] = a_part;
    prim.indices = a_idx;
    prim.material = static_cast<int>(model.materials.size() - 1);
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Mesh gm;
    gm.name = mesh_label_name(label);
    gm.primitives.push_back(prim);
    model.meshes.push_back(gm);
    tinygltf::Node node;
    node.name = mesh_label_name(label);
    node.mesh = static_cast<int>(model.meshes.size() - 1);
    model.nodes.push_back(node);
    children.push_back(static_cast<int>(model.nodes.size() - 1));
  }
  // Root: floorcast's world is z up, glTF's y up: -90 degrees about x maps +z to +y.
  tinygltf::Node root;
  root.name = "building";
  root.rotation = {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};
  root.children = children;
  tinygltf::Value::Object root_extras;
  root_extras["frame"] = tinygltf::Value(std::string("children in floorcast's world frame (x, y plan metres, z up); this node rotates it to glTF's y up"));
  root.extras = tinygltf::Value(root_extras);
  model.nodes.push_back(root);
  scene.nodes.push_back(static_cast<int>(model.nodes.size() - 1));
  if (!metadata.is_object()) throw InputError(path + ": glTF metadata must be a JSON object");
  tinygltf::Value::Object extras;
  for (auto it = metadata.begin(); it != metadata.end(); ++it) {
    const nlohmann::json& v = it.value();
    if (v.is_string()) extras[it.key()] = tinygltf::Value(v.get<std::string>());
    else if (v.is_boolean()) extras[it.key()] = tinygltf::Value(v.get<bool>());
    else if (v.is_number_integer()) extras[it.key()] = tinygltf::Value(static_cast<int>(v.get<long long>()));
    else if (v.is_number()) extras[it.key()] = tinygltf::Value(v.get<double>());
    else throw InputError(path + ": glTF metadata \"" + it.key() + "\" must be a string, number or boolean");
  }
  scene.extras = tinygltf::Value(extras);
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, out, false, true)) throw InputError(path + ": cannot encode glTF");
  write_text_file_atomic(path, out.str());
}

Mesh load_mesh_glb(const std::string& path, nlohmann::json* metadata) {
  const std::string bytes = read_text_file(path);
  if (bytes.size() < 12 || bytes.compare(0, 4, "glTF") != 0) throw InputError(path + ": not a binary glTF (.glb) file");
  if (bytes.size() > 0xffffffffULL) throw InputError(path + ": file too large");
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  const bool ok = loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                              static_cast<unsigned>(bytes.size()), "");
  if (!ok) throw InputError(path + ": cannot read glTF: " + err);
  Mesh mesh;
  for (std::size_t mi = 0; mi < model.meshes.size(); ++mi) {
    const tinygltf::Mesh& gm = model.meshes[mi];
    for (std::size_t pi = 0; pi < gm.primitives.size(); ++pi) {
      const tinygltf::Primitive& prim = gm.primitives[pi];
      const std::string where = "meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(pi) + "]";
      if (prim.mode != TINYGLTF_MODE_TRIANGLES) throw InputError(path + ": " + where + ": not a triangle list");
      if (prim.material < 0 || static_cast<std::size_t>(prim.material) >= model.materials.size()) {
        throw InputError(path + ": " + where + ": no material (the label is the material name)");
      }
      MeshLabel label;
      const std::string& mname = model.materials[static_cast<std::size_t>(prim.material)].name;
      if (!mesh_label_from_name(mname, label)) {
        throw InputError(path + ": " + where + ": material \"" + mname + "\" is not a floorcast label");
      }
      const auto pos_it = prim.attributes.find("POSITION");
      if (pos_it == prim.attributes.end()) throw InputError(path + ": " + where + ": no POSITION attribute");
      const AccessorReader pos(model, pos_it->second, path, where + ".POSITION");
      if (pos.components() != 3 || pos.component_type() != TINYGLTF_COMPONENT_TYPE_FLOAT) {
        throw InputError(path + ": " + where + ": POSITION must be float VEC3");
      }
      std::unique_ptr<AccessorReader> part;
      const auto part_it = prim.attributes.find("_PART_ID");
      if (part_it != prim.attributes.end()) {
        part = std::make_unique<AccessorReader>(model, part_it->second, path, where + "._PART_ID");
        if (part->count() != pos.count()) throw InputError(path + ": " + where + ": _PART_ID count differs from POSITION");
      }
      if (prim.indices < 0) throw InputError(path + ": " + where + ": not indexed");
      const AccessorReader idx(model, prim.indices, path, where + ".indices");
      if (idx.count() % 3 != 0) throw InputError(path + ": " + where + ": index count not a multiple of 3");
      const int base = static_cast<int>(mesh.vertices_m.size());
      for (std::size_t v = 0; v < pos.count(); ++v) {
        const Eigen::Vector3f p(static_cast<float>(pos.get(v, 0)), static_cast<float>(pos.get(v, 1)),
                                static_cast<float>(pos.get(v, 2)));
        if (!p.allFinite()) throw InputError(path + ": " + where + ": non-finite vertex");
        mesh.vertices_m.push_back(p);
      }
      for (std::size_t t = 0; t < idx.count() / 3; ++t) {
        Eigen::Vector3i tri;
        for (int k = 0; k < 3; ++k) {
          const double i = idx.get(3 * t + static_cast<std::size_t>(k), 0);
          if (i >= static_cast<double>(pos.count())) throw InputError(path + ": " + where + ": index out of range");
          tri[k] = base + static_cast<int>(i);
        }
        mesh.triangles.push_back(tri);
        mesh.labels.push_back(label);
        mesh.part_ids.push_back(part ? static_cast<int>(part->get(static_cast<std::size_t>(tri[0] - base), 0)) : -1);
      }
    }
  }
  if (metadata) {
    *metadata = nlohmann::json::object();
    if (!model.scenes.empty() && model.scenes[0].extras.IsObject()) {
      for (const std::string& k : model.scenes[0].extras.Keys()) {
        const tinygltf::Value& v = model.scenes[0].extras.Get(k);
        if (v.IsString()) (*metadata)[k] = v.Get<std::string>();
        else if (v.IsBool()) (*metadata)[k] = v.Get<bool>();
        else if (v.IsInt()) (*metadata)[k] = v.Get<int>();
        else if (v.IsNumber()) (*metadata)[k] = v.GetNumberAsDouble();
      }
    }
  }
  return mesh;
}

}  // namespace floorcast
