// The appended-data section of a VTK XML file (VTK's "VTK XML file formats", binary
// appended data), shared by the particle (.vtu) and grid (.vtr) writers: every array either
// raw (a UInt64 byte count, then the bytes) or zlib-compressed (compressor
// "vtkZLibDataCompressor": a UInt64 header [number of blocks, block size, size of the last
// block if partial else 0, compressed size of each block], then the compressed blocks).
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace skred::vtk {

// One DataArray of the appended section: `items` items of `item_bytes` bytes each, produced
// by fill(begin, end, out), which writes items [begin, end) to out ((end - begin) *
// item_bytes bytes). fill may be called concurrently for disjoint ranges.
struct AppendedArray {
  std::size_t items = 0;
  std::size_t item_bytes = 0;
  std::function<void(std::size_t begin, std::size_t end, unsigned char* out)> fill;
};

// The `<VTKFile ...>` opening line of a file of `type` (UnstructuredGrid, RectilinearGrid),
// with header_type UInt64, the machine's byte order and, if `compress`, the zlib compressor.
std::string vtkfile_element(const char* type, bool compress);

// ` offset="N"` padded to a fixed width, so a header written before the offsets are known can
// be rewritten in place with them.
std::string offset_attribute(std::uint64_t offset);

// Writes header(offsets) (the XML up to and including `<AppendedData encoding="raw">` and
// the underscore), each array in order, and `footer`; header is first called with zero
// offsets, then once more with each array's offset within the appended data, and rewritten
// in place (it must have the same length: use offset_attribute). `os` must be seekable.
void write_appended(std::ostream& os,
                    const std::function<std::string(const std::vector<std::uint64_t>& offsets)>& header,
                    const std::vector<AppendedArray>& arrays, bool compress, const std::string& footer);

}  // namespace skred::vtk
