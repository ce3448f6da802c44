#include "core/GmshApi.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <memory>
#include <stdexcept>

#include "core/MeshFileError.hpp"

extern "C" {
#include <gmshc.h>
}

namespace keller {

// The C API functions used, typed from gmshc.h's declarations.
struct GmshApi::Functions {
  decltype(&::gmshFree) gmshFree = nullptr;
  decltype(&::gmshInitialize) gmshInitialize = nullptr;
  decltype(&::gmshFinalize) gmshFinalize = nullptr;
  decltype(&::gmshOptionSetNumber) gmshOptionSetNumber = nullptr;
  decltype(&::gmshLoggerStart) gmshLoggerStart = nullptr;
  decltype(&::gmshLoggerGet) gmshLoggerGet = nullptr;
  decltype(&::gmshLoggerStop) gmshLoggerStop = nullptr;
  decltype(&::gmshOpen) gmshOpen = nullptr;
  decltype(&::gmshWrite) gmshWrite = nullptr;
  decltype(&::gmshModelMeshGenerate) gmshModelMeshGenerate = nullptr;
  decltype(&::gmshModelGetDimension) gmshModelGetDimension = nullptr;
  decltype(&::gmshModelGetPhysicalGroups) gmshModelGetPhysicalGroups = nullptr;
  decltype(&::gmshModelGetPhysicalName) gmshModelGetPhysicalName = nullptr;
  decltype(&::gmshModelGetEntitiesForPhysicalGroup) gmshModelGetEntitiesForPhysicalGroup = nullptr;
  decltype(&::gmshModelMeshGetElements) gmshModelMeshGetElements = nullptr;
  decltype(&::gmshModelMeshGetElementProperties) gmshModelMeshGetElementProperties = nullptr;
  decltype(&::gmshModelMeshGetNodes) gmshModelMeshGetNodes = nullptr;
  decltype(&::gmshModelAdd) gmshModelAdd = nullptr;
  decltype(&::gmshModelAddDiscreteEntity) gmshModelAddDiscreteEntity = nullptr;
  decltype(&::gmshModelMeshAddNodes) gmshModelMeshAddNodes = nullptr;
  decltype(&::gmshModelMeshAddElementsByType) gmshModelMeshAddElementsByType = nullptr;
  decltype(&::gmshModelAddPhysicalGroup) gmshModelAddPhysicalGroup = nullptr;
  decltype(&::gmshModelSetPhysicalName) gmshModelSetPhysicalName = nullptr;
};

namespace {

// The library CMake found (KELLER_GMSH_LIBRARY: its real path, set by CMakeLists.txt).
const char* const kLibrary = KELLER_GMSH_LIBRARY;

struct Loaded {
  GmshApi::Functions functions;
  std::string error;  // empty when loaded
};

template <class F>
void bind(void* handle, const char* name, F& function, std::string& error) {
  function = reinterpret_cast<F>(dlsym(handle, name));
  if (!function) error += std::string(error.empty() ? "" : ", ") + "no function " + name;
}

Loaded load() {
  Loaded out;
  void* handle = dlopen(kLibrary, RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    out.error = dlerror();
    return out;
  }
  GmshApi::Functions& f = out.functions;
  bind(handle, "gmshFree", f.gmshFree, out.error);
  bind(handle, "gmshInitialize", f.gmshInitialize, out.error);
  bind(handle, "gmshFinalize", f.gmshFinalize, out.error);
  bind(handle, "gmshOptionSetNumber", f.gmshOptionSetNumber, out.error);
  bind(handle, "gmshLoggerStart", f.gmshLoggerStart, out.error);
  bind(handle, "gmshLoggerGet", f.gmshLoggerGet, out.error);
  bind(handle, "gmshLoggerStop", f.gmshLoggerStop, out.error);
  bind(handle, "gmshOpen", f.gmshOpen, out.error);
  bind(handle, "gmshWrite", f.gmshWrite, out.error);
  bind(handle, "gmshModelMeshGenerate", f.gmshModelMeshGenerate, out.error);
  bind(handle, "gmshModelGetDimension", f.gmshModelGetDimension, out.error);
  bind(handle, "gmshModelGetPhysicalGroups", f.gmshModelGetPhysicalGroups, out.error);
  bind(handle, "gmshModelGetPhysicalName", f.gmshModelGetPhysicalName, out.error);
  bind(handle, "gmshModelGetEntitiesForPhysicalGroup", f.gmshModelGetEntitiesForPhysicalGroup, out.error);
  bind(handle, "gmshModelMeshGetElements", f.gmshModelMeshGetElements, out.error);
  bind(handle, "gmshModelMeshGetElementProperties", f.gmshModelMeshGetElementProperties, out.error);
  bind(handle, "gmshModelMeshGetNodes", f.gmshModelMeshGetNodes, out.error);
  bind(handle, "gmshModelAdd", f.gmshModelAdd, out.error);
  bind(handle, "gmshModelAddDiscreteEntity", f.gmshModelAddDiscreteEntity, out.error);
  bind(handle, "gmshModelMeshAddNodes", f.gmshModelMeshAddNodes, out.error);
  bind(handle, "gmshModelMeshAddElementsByType", f.gmshModelMeshAddElementsByType, out.error);
  bind(handle, "gmshModelAddPhysicalGroup", f.gmshModelAddPhysicalGroup, out.error);
  bind(handle, "gmshModelSetPhysicalName", f.gmshModelSetPhysicalName, out.error);
  return out;
}

void check(int ierr, const char* call) {
  if (ierr != 0) {
    throw std::runtime_error(
        fmt::format("Gmsh's {} failed (it stopped on an exception: a damaged file, or more "
                    "memory than the file can need)",
                    call));
  }
}

// The C API takes non-const pointers to the arrays it only reads.
template <class T>
T* in(const std::vector<T>& v) {
  return const_cast<T*>(v.data());
}

// An array Gmsh allocated, freed with gmshFree.
template <class T>
struct Owned {
  const GmshApi::Functions& f;
  T* p = nullptr;
  std::size_t n = 0;
  ~Owned() { f.gmshFree(p); }
  std::vector<T> vector() const { return std::vector<T>(p, p + n); }
};

}  // namespace

GmshApi& GmshApi::get(const std::string& file) {
  static const Loaded loaded = load();
  if (!loaded.error.empty()) {
    throw MeshFileError(
        fmt::format("{}: cannot load the Gmsh library {} ({}); install it (Debian: libgmsh-dev) "
                    "and build keller again",
                    file, kLibrary, loaded.error));
  }
  static GmshApi api(loaded.functions);
  return api;
}

void GmshApi::initialize() {
  int ierr = 0;
  std::string program = "keller";
  char* argv[] = {program.data()};
  f_.gmshInitialize(1, argv, 0, &ierr);  // no configuration files: a mesh does not depend on the user
  check(ierr, "initialize");
}

void GmshApi::finalize() {
  int ierr = 0;
  f_.gmshFinalize(&ierr);
  check(ierr, "finalize");
}

void GmshApi::set_option(const std::string& name, double value) {
  int ierr = 0;
  f_.gmshOptionSetNumber(name.c_str(), value, &ierr);
  check(ierr, "option::setNumber");
}

void GmshApi::logger_start() {
  int ierr = 0;
  f_.gmshLoggerStart(&ierr);
  check(ierr, "logger::start");
}

std::vector<std::string> GmshApi::logger_get() {
  int ierr = 0;
  char** log = nullptr;
  std::size_t n = 0;
  f_.gmshLoggerGet(&log, &n, &ierr);
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n; ++i) {
    out.emplace_back(log[i]);
    f_.gmshFree(log[i]);
  }
  f_.gmshFree(log);
  check(ierr, "logger::get");
  return out;
}

void GmshApi::logger_stop() {
  int ierr = 0;
  f_.gmshLoggerStop(&ierr);
  check(ierr, "logger::stop");
}

void GmshApi::open(const std::string& path) {
  int ierr = 0;
  f_.gmshOpen(path.c_str(), &ierr);
  check(ierr, "open");
}

void GmshApi::write(const std::string& path) {
  int ierr = 0;
  f_.gmshWrite(path.c_str(), &ierr);
  check(ierr, "write");
}

void GmshApi::generate(int dim) {
  int ierr = 0;
  f_.gmshModelMeshGenerate(dim, &ierr);
  check(ierr, "model::mesh::generate");
}

int GmshApi::dimension() {
  int ierr = 0;
  const int dim = f_.gmshModelGetDimension(&ierr);
  check(ierr, "model::getDimension");
  return dim;
}

std::vector<std::pair<int, int>> GmshApi::physical_groups(int dim) {
  int ierr = 0;
  Owned<int> dim_tags{f_};
  f_.gmshModelGetPhysicalGroups(&dim_tags.p, &dim_tags.n, dim, &ierr);
  check(ierr, "model::getPhysicalGroups");
  std::vector<std::pair<int, int>> out;
  for (std::size_t i = 0; i + 1 < dim_tags.n; i += 2) out.emplace_back(dim_tags.p[i], dim_tags.p[i + 1]);
  return out;
}

std::string GmshApi::physical_name(int dim, int tag) {
  int ierr = 0;
  Owned<char> name{f_};
  f_.gmshModelGetPhysicalName(dim, tag, &name.p, &ierr);
  check(ierr, "model::getPhysicalName");
  return name.p ? std::string(name.p) : std::string();
}

std::vector<int> GmshApi::entities_for_physical_group(int dim, int tag) {
  int ierr = 0;
  Owned<int> tags{f_};
  f_.gmshModelGetEntitiesForPhysicalGroup(dim, tag, &tags.p, &tags.n, &ierr);
  check(ierr, "model::getEntitiesForPhysicalGroup");
  return tags.vector();
}

GmshApi::Elements GmshApi::elements(int dim, int tag) {
  int ierr = 0;
  Owned<int> types{f_};
  Owned<std::size_t*> tags{f_}, nodes{f_};
  Owned<std::size_t> tags_n{f_}, nodes_n{f_};
  f_.gmshModelMeshGetElements(&types.p, &types.n, &tags.p, &tags_n.p, &tags.n, &nodes.p, &nodes_n.p, &nodes.n, dim, tag,
                              &ierr);
  Elements out;
  out.types = types.vector();
  for (std::size_t t = 0; t < tags.n; ++t) {
    out.tags.emplace_back(tags.p[t], tags.p[t] + tags_n.p[t]);
    f_.gmshFree(tags.p[t]);
  }
  for (std::size_t t = 0; t < nodes.n; ++t) {
    out.nodes.emplace_back(nodes.p[t], nodes.p[t] + nodes_n.p[t]);
    f_.gmshFree(nodes.p[t]);
  }
  check(ierr, "model::mesh::getElements");
  return out;
}

GmshApi::ElementType GmshApi::element_type(int type) {
  int ierr = 0;
  ElementType out;
  Owned<char> name{f_};
  Owned<double> coords{f_};
  f_.gmshModelMeshGetElementProperties(type, &name.p, &out.dim, &out.order, &out.num_nodes, &coords.p, &coords.n,
                                       &out.num_primary_nodes, &ierr);
  check(ierr, "model::mesh::getElementProperties");
  out.name = name.p ? name.p : "";
  return out;
}

void GmshApi::nodes(std::vector<std::size_t>& tags, std::vector<double>& coords) {
  int ierr = 0;
  Owned<std::size_t> t{f_};
  Owned<double> c{f_}, params{f_};
  f_.gmshModelMeshGetNodes(&t.p, &t.n, &c.p, &c.n, &params.p, &params.n, -1, -1, 0, 0, &ierr);
  check(ierr, "model::mesh::getNodes");
  tags = t.vector();
  coords = c.vector();
}

void GmshApi::add_model(const std::string& name) {
  int ierr = 0;
  f_.gmshModelAdd(name.c_str(), &ierr);
  check(ierr, "model::add");
}

void GmshApi::add_discrete_entity(int dim, int tag) {
  int ierr = 0;
  f_.gmshModelAddDiscreteEntity(dim, tag, nullptr, 0, &ierr);
  check(ierr, "model::addDiscreteEntity");
}

void GmshApi::add_nodes(int dim, int tag, const std::vector<std::size_t>& tags, const std::vector<double>& coords) {
  int ierr = 0;
  f_.gmshModelMeshAddNodes(dim, tag, in(tags), tags.size(), in(coords), coords.size(), nullptr, 0, &ierr);
  check(ierr, "model::mesh::addNodes");
}

void GmshApi::add_elements_by_type(int tag, int type, const std::vector<std::size_t>& tags,
                                   const std::vector<std::size_t>& nodes) {
  int ierr = 0;
  f_.gmshModelMeshAddElementsByType(tag, type, in(tags), tags.size(), in(nodes), nodes.size(), &ierr);
  check(ierr, "model::mesh::addElementsByType");
}

void GmshApi::add_physical_group(int dim, const std::vector<int>& entities, int tag) {
  int ierr = 0;
  f_.gmshModelAddPhysicalGroup(dim, in(entities), entities.size(), tag, &ierr);
  check(ierr, "model::addPhysicalGroup");
}

void GmshApi::set_physical_name(int dim, int tag, const std::string& name) {
  int ierr = 0;
  f_.gmshModelSetPhysicalName(dim, tag, name.c_str(), &ierr);
  check(ierr, "model::setPhysicalName");
}

}  // namespace keller
