// A look at a netCDF classic file's header before libnetcdf reads it:
// libnetcdf 4.9 allocates what the header claims (a name of 2 GB in a
// file of 24 KB), so the Exodus reader checks first that every length and
// count the header gives fits in the file.
#pragma once

#include <string>

namespace dtm {

// Throws FormatError naming `path` and the byte where a classic netCDF
// header (CDF-1, CDF-2 or CDF-5: the format of the Unidata netCDF
// specification, "The NetCDF Classic Format") is cut short, claims a name,
// an attribute, a list or a variable's data beyond the file's end, or a
// name longer than netCDF's 256 bytes (which libnetcdf copies into
// buffers of that size whatever its length).
// Does nothing to other files (netCDF-4's HDF5, or no netCDF at all: the
// library says which).
void check_netcdf_header(const std::string& path);

}  // namespace dtm
