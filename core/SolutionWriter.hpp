// Writes meshes and solution fields into HDF5 groups, and XDMF files beside them that ParaView
// (and VisIt, meshio) open: one spatial collection of 9-node quadrilateral grids per solution,
// one grid per element group, nodal fields by component and as vectors, P1-discontinuous
// fields as cell data (their element-centre values).
#pragma once

#include <string>
#include <vector>

#include "core/H5File.hpp"
#include "core/Mesh.hpp"
#include "core/SolutionFields.hpp"

namespace keller {

// /<group>/nodes (N x 2), elements (E x 9, ReferenceElement order), element_group (E),
// boundaries/<name> (k x 2: element, edge), and xdmf/<group>_topology in VTK order.
void write_mesh(H5File& file, const std::string& group, const Mesh& mesh);

// Fields of one solution into /<group>: nodal fields as (N x c) datasets, element fields as
// (E x 3c) coefficient datasets, arrays as they are; attributes basis and components on each.
// Also writes what the XDMF needs (deformed node positions, per-group cell data).
void write_fields(H5File& file, const std::string& group, const SolutionFields& fields);

struct XdmfSolution {
  std::string group;  // HDF5 group the fields were written to
  std::string label;  // shown in ParaView's time/selector, e.g. "point 12 (Wi = 0.3)"
  double time = 0.0;  // position in the temporal collection (e.g. the parameter value)
};

// Writes (atomically: temporary file then rename) an XDMF file for the listed solutions of an
// HDF5 file whose mesh is in /<mesh_group>. h5_name is the HDF5 file name as the XDMF should
// reference it (relative to the XDMF file; written escaped for XML, as are the labels). The
// temporary file is created exclusively (PendingFile); throws IoError where it cannot be written.
void write_xdmf(const std::string& xdmf_path, const std::string& h5_name, const std::string& mesh_group,
                const Mesh& mesh, const std::vector<XdmfSolution>& solutions, const SolutionFields& layout);

}  // namespace keller
