// result.xmf: an XDMF 3 description of result.h5, so that ParaView (and any Xdmf3 or VTK
// reader) opens the saved fields of a run over time without knowing the HDF5 layout.
#pragma once

#include <filesystem>
#include <string>

namespace fretbem::io {

/// Writes `xmf` describing the step groups under `parent` in the HDF5 file `h5` (written by
/// Hdf5Writer::describe and write_step_fields): one temporal collection, one uniform grid per
/// saved step (its `time` attribute as the time value), a 3DCoRectMesh of grid_shape cells in
/// x and y, one node thick at z = 0 (ParaView's Xdmf3 readers: a map in the x-y plane), with origin and spacing from the file's attributes (m; geometry in double
/// precision, `Precision="8"`), every 2-D dataset of the step as a cell-centred scalar attribute,
/// and the initial surface (`surface_initial`) on every step. Data stay in `h5`, referenced by its
/// file name (the two files sit side by side). Returns false, writing nothing, when `parent`
/// holds no step group. Throws std::runtime_error naming the file on a read or write failure.
bool write_xdmf(const std::filesystem::path& h5, const std::filesystem::path& xmf,
                const std::string& parent = "/fields");

}  // namespace fretbem::io
