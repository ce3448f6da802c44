#include "core/SolutionWriter.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "core/PendingFile.hpp"

namespace keller {

namespace {

constexpr int kVtkOrder[9] = {0, 2, 8, 6, 1, 5, 7, 3, 4};

std::vector<int> group_elements(const Mesh& mesh, int g) { return mesh.elements_in_group(g); }

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

// Row-major copy of an Eigen (column-major) matrix.
std::vector<double> row_major(const Eigen::MatrixXd& m) {
  std::vector<double> out(static_cast<size_t>(m.size()));
  for (long i = 0; i < m.rows(); ++i)
    for (long j = 0; j < m.cols(); ++j) out[static_cast<size_t>(i * m.cols() + j)] = m(i, j);
  return out;
}

// `text` with the characters XML gives a meaning (& < > " ') as entities.
std::string xml_escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

void write_mesh(H5File& file, const std::string& group, const Mesh& mesh) {
  file.create_group(group);
  std::vector<double> xy;
  for (const auto& p : mesh.nodes()) {
    xy.push_back(p[0]);
    xy.push_back(p[1]);
  }
  file.write_matrix(group + "/nodes", xy.data(), mesh.num_nodes(), 2);
  std::vector<int> conn, grp;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    for (int a = 0; a < 9; ++a) conn.push_back(mesh.element(e)[a]);
    grp.push_back(mesh.element_group(e));
  }
  file.write_int_matrix(group + "/elements", conn.data(), mesh.num_elements(), 9);
  file.write_int_matrix(group + "/element_group", grp.data(), mesh.num_elements(), 1);
  file.write_strings(group + "/group_names", mesh.group_names());
  file.set_attribute(group + "/elements", "node_order",
                     std::string("lexicographic: node i + 3 j at reference (s_i, t_j), s, t in {-1, 0, 1}"));
  for (const std::string& name : mesh.boundary_names()) {
    std::vector<int> be;
    for (const BoundaryEdge& b : mesh.boundary(name)) {
      be.push_back(b.element);
      be.push_back(b.edge);
    }
    file.write_int_matrix(group + "/boundaries/" + name, be.data(), static_cast<long>(be.size() / 2), 2);
  }
  for (int g = 0; g < static_cast<int>(mesh.group_names().size()); ++g) {
    std::vector<int> topo;
    for (int e : group_elements(mesh, g))
      for (int k : kVtkOrder) topo.push_back(mesh.element(e)[k]);
    file.write_int_matrix(group + "/xdmf/" + mesh.group_names()[g] + "_topology", topo.data(),
                          static_cast<long>(topo.size() / 9), 9);
  }
}

void write_fields(H5File& file, const std::string& group, const SolutionFields& fields) {
  file.create_group(group);
  const Mesh* mesh = fields.mesh;
  if (mesh) {
    std::vector<double> xy;
    for (const auto& p : mesh->nodes()) {
      xy.push_back(p[0]);
      xy.push_back(p[1]);
    }
    file.write_matrix(group + "/xdmf/nodes", xy.data(), mesh->num_nodes(), 2);
  }
  for (const NodalField& f : fields.nodal) {
    const std::string ds = group + "/" + f.name;
    const auto data = row_major(f.values);
    file.write_matrix(ds, data.data(), f.values.rows(), f.values.cols());
    file.set_attribute(ds, "basis", f.basis);
    file.set_attribute(ds, "components", join(f.components));
    file.set_attribute(ds, "groups", join(f.groups));
    for (long k = 0; k < f.values.cols(); ++k) {  // one dataset per component for the XDMF readers
      const Eigen::VectorXd col = f.values.col(k);
      file.write_matrix(group + "/xdmf/" + f.name + "_" + f.components[k], col.data(), col.size(), 1);
    }
    if (f.values.cols() == 2) {  // ParaView wants 3-component vectors
      std::vector<double> v3;
      for (long i = 0; i < f.values.rows(); ++i) {
        v3.push_back(f.values(i, 0));
        v3.push_back(f.values(i, 1));
        v3.push_back(0.0);
      }
      file.write_matrix(group + "/xdmf/" + f.name + "_vector", v3.data(), f.values.rows(), 3);
    }
  }
  for (const ElementField& f : fields.element) {
    const std::string ds = group + "/" + f.name;
    const auto data = row_major(f.coefficients);
    file.write_matrix(ds, data.data(), f.coefficients.rows(), f.coefficients.cols());
    file.set_attribute(ds, "basis", f.basis);
    file.set_attribute(ds, "components", join(f.components));
    file.set_attribute(ds, "groups", join(f.groups));
    file.set_attribute(ds, "layout",
                       std::string("element x (3 * component): c0 + c1 (x - xc) + c2 (y - yc), xc = centre node"));
    if (mesh) {
      for (int g = 0; g < static_cast<int>(mesh->group_names().size()); ++g) {
        const auto els = group_elements(*mesh, g);
        for (long c = 0; c < f.centre_values.cols(); ++c) {
          std::vector<double> cv;
          for (int e : els) cv.push_back(f.centre_values(e, c));
          file.write_matrix(group + "/xdmf/" + f.components[c] + "_" + mesh->group_names()[g], cv.data(),
                            static_cast<long>(els.size()), 1);
        }
      }
    }
  }
  for (const NamedArray& a : fields.arrays) {
    const std::string ds = group + "/" + a.name;
    const auto data = row_major(a.values);
    file.write_matrix(ds, data.data(), a.values.rows(), a.values.cols());
    file.set_attribute(ds, "columns", join(a.columns));
    if (!a.doc.empty()) file.set_attribute(ds, "doc", a.doc);
  }
}

void write_xdmf(const std::string& xdmf_path, const std::string& h5_file_name, const std::string& mesh_group,
                const Mesh& mesh, const std::vector<XdmfSolution>& solutions, const SolutionFields& layout) {
  const std::string h5_name = xml_escaped(h5_file_name);
  std::string x;
  x += "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n";
  const bool temporal = solutions.size() > 1;
  if (temporal) x += "  <Grid Name=\"solutions\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  const int N = mesh.num_nodes();
  for (const XdmfSolution& s : solutions) {
    x +=
        fmt::format("   <Grid Name=\"{}\" GridType=\"Collection\" CollectionType=\"Spatial\">\n", xml_escaped(s.label));
    if (temporal) x += fmt::format("    <Time Value=\"{}\" />\n", s.time);
    for (int g = 0; g < static_cast<int>(mesh.group_names().size()); ++g) {
      const std::string& gname = mesh.group_names()[g];
      const long E = static_cast<long>(mesh.elements_in_group(g).size());
      if (E == 0) continue;
      x += fmt::format("    <Grid Name=\"{}\" GridType=\"Uniform\">\n", gname);
      x += fmt::format(
          "     <Topology TopologyType=\"Quadrilateral_9\" NumberOfElements=\"{}\">\n"
          "      <DataItem Dimensions=\"{} 9\" NumberType=\"Int\" Precision=\"4\" "
          "Format=\"HDF\">{}:/{}/xdmf/{}_topology"
          "</DataItem>\n     </Topology>\n",
          E, E, h5_name, mesh_group, gname);
      x += fmt::format(
          "     <Geometry GeometryType=\"XY\">\n"
          "      <DataItem Dimensions=\"{} 2\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{}:/{}/xdmf/nodes"
          "</DataItem>\n     </Geometry>\n",
          N, h5_name, s.group);
      auto lives_here = [&](const std::vector<std::string>& groups) {
        return groups.empty() || std::find(groups.begin(), groups.end(), gname) != groups.end();
      };
      for (const NodalField& f : layout.nodal) {
        if (!lives_here(f.groups)) continue;
        const long nc = f.values.cols();
        if (nc == 2)
          x += fmt::format(
              "     <Attribute Name=\"{}\" AttributeType=\"Vector\" Center=\"Node\">\n"
              "      <DataItem Dimensions=\"{} 3\" NumberType=\"Float\" Precision=\"8\" "
              "Format=\"HDF\">{}:/{}/xdmf/{}_vector"
              "</DataItem>\n     </Attribute>\n",
              f.name, N, h5_name, s.group, f.name);
        for (long c = 0; c < nc; ++c)
          x += fmt::format(
              "     <Attribute Name=\"{}\" AttributeType=\"Scalar\" Center=\"Node\">\n"
              "      <DataItem Dimensions=\"{}\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{}:/{}/xdmf/{}_{}"
              "</DataItem>\n     </Attribute>\n",
              f.components[c], N, h5_name, s.group, f.name, f.components[c]);
      }
      for (const ElementField& f : layout.element) {
        if (!lives_here(f.groups)) continue;
        const long nc = f.centre_values.cols();
        for (long c = 0; c < nc; ++c)
          x += fmt::format(
              "     <Attribute Name=\"{}\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
              "      <DataItem Dimensions=\"{}\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{}:/{}/xdmf/{}_{}"
              "</DataItem>\n     </Attribute>\n",
              f.components[c], E, h5_name, s.group, f.components[c], gname);
      }
      x += "    </Grid>\n";
    }
    x += "   </Grid>\n";
  }
  if (temporal) x += "  </Grid>\n";
  x += " </Domain>\n</Xdmf>\n";

  PendingFile file(xdmf_path);
  file.write(x);
  file.commit();
}

}  // namespace keller
