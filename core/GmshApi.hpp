// The Gmsh library, loaded (dlopen) in the child process that reads or writes a Gmsh file
// (core/GmshProcess.hpp) rather than linked: libgmsh brings some 80 libraries (OpenCASCADE, FLTK,
// X11, OpenGL, image codecs) whose loading and static initialisers would cost every keller process
// about 0.3 s and 45 MB, Gmsh file or not; linked, the executable's copies of Eigen functions
// (built with -march=native) also replaced libgmsh's own inside Gmsh, which crashed it. Calls go
// through Gmsh's C API (gmshc.h), wrapped here in C++ types; a call that sets Gmsh's error flag
// throws std::runtime_error naming it.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace keller {

class GmshApi {
 public:
  // The loaded library (loaded on the first call). Throws MeshFileError naming `file` (the file
  // that needed it) and the library when it cannot be loaded.
  static GmshApi& get(const std::string& file);

  void initialize();
  void finalize();
  void set_option(const std::string& name, double value);
  void logger_start();
  std::vector<std::string> logger_get();
  void logger_stop();

  void open(const std::string& path);
  void write(const std::string& path);
  void generate(int dim);

  int dimension();
  std::vector<std::pair<int, int>> physical_groups(int dim);
  std::string physical_name(int dim, int tag);
  std::vector<int> entities_for_physical_group(int dim, int tag);
  struct Elements {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> tags, nodes;  // per type
  };
  Elements elements(int dim, int tag);
  struct ElementType {
    std::string name;
    int dim = 0, order = 0, num_nodes = 0, num_primary_nodes = 0;
  };
  ElementType element_type(int type);
  // Every node of the model: tags, and x y z of each.
  void nodes(std::vector<std::size_t>& tags, std::vector<double>& coords);

  void add_model(const std::string& name);
  void add_discrete_entity(int dim, int tag);
  void add_nodes(int dim, int tag, const std::vector<std::size_t>& tags, const std::vector<double>& coords);
  void add_elements_by_type(int tag, int type, const std::vector<std::size_t>& tags,
                            const std::vector<std::size_t>& nodes);
  void add_physical_group(int dim, const std::vector<int>& entities, int tag);
  void set_physical_name(int dim, int tag, const std::string& name);

  struct Functions;

 private:
  explicit GmshApi(const Functions& f) : f_(f) {}
  const Functions& f_;
};

}  // namespace keller
