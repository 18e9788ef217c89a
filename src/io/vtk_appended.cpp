#include "io/vtk_appended.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <stdexcept>

namespace skred::vtk {

namespace {

constexpr std::size_t kChunkItems = 1 << 14;  // items per fill call
constexpr std::size_t kBlockBytes = 1 << 18;  // uncompressed bytes per zlib block (VTK: any size)
// zlib level 1 (fastest): the slope example's last default frame shrinks to 0.557 of its raw
// size, against 0.552 at the default level 6, which took 4 times as long (recompressed with
// Python's zlib).
constexpr int kZlibLevel = 1;
constexpr int kOffsetWidth = 20;  // digits of a UInt64

// The array's bytes, filled chunk by chunk in parallel.
std::vector<unsigned char> raw_bytes(const AppendedArray& a) {
  std::vector<unsigned char> raw(a.items * a.item_bytes);
  const long chunks = static_cast<long>((a.items + kChunkItems - 1) / kChunkItems);
#pragma omp parallel for schedule(dynamic)
  for (long c = 0; c < chunks; ++c) {
    const std::size_t begin = static_cast<std::size_t>(c) * kChunkItems;
    const std::size_t end = std::min(a.items, begin + kChunkItems);
    a.fill(begin, end, raw.data() + begin * a.item_bytes);
  }
  return raw;
}

void put_u64s(std::ostream& os, const std::vector<std::uint64_t>& v) {
  os.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof v[0]));
}

// One array zlib-compressed in blocks of kBlockBytes (all full but the last), the blocks in
// parallel; returns the bytes written.
std::uint64_t write_compressed(std::ostream& os, const std::vector<unsigned char>& raw) {
  const std::size_t n = raw.size();
  const std::size_t blocks = (n + kBlockBytes - 1) / kBlockBytes;
  std::vector<std::vector<unsigned char>> packed(blocks);
  bool failed = false;
#pragma omp parallel for schedule(dynamic)
  for (long b = 0; b < static_cast<long>(blocks); ++b) {
    const std::size_t begin = static_cast<std::size_t>(b) * kBlockBytes;
    const std::size_t size = std::min(kBlockBytes, n - begin);
    std::vector<unsigned char>& out = packed[static_cast<std::size_t>(b)];
    out.resize(compressBound(static_cast<uLong>(size)));
    uLongf got = static_cast<uLongf>(out.size());
    if (compress2(out.data(), &got, raw.data() + begin, static_cast<uLong>(size), kZlibLevel) != Z_OK) {
#pragma omp atomic write
      failed = true;
    }
    out.resize(got);
  }
  if (failed) throw std::runtime_error("zlib could not compress a VTK data block");
  std::vector<std::uint64_t> header = {blocks, kBlockBytes, n % kBlockBytes};
  for (const auto& p : packed) header.push_back(p.size());
  put_u64s(os, header);
  std::uint64_t bytes = header.size() * sizeof(std::uint64_t);
  for (const auto& p : packed) {
    os.write(reinterpret_cast<const char*>(p.data()), static_cast<std::streamsize>(p.size()));
    bytes += p.size();
  }
  return bytes;
}

}  // namespace

std::string vtkfile_element(const char* type, bool compress) {
  constexpr bool little = std::endian::native == std::endian::little;
  return fmt::format("<VTKFile type=\"{}\" version=\"1.0\" byte_order=\"{}\" header_type=\"UInt64\"{}>\n",
                     type, little ? "LittleEndian" : "BigEndian",
                     compress ? " compressor=\"vtkZLibDataCompressor\"" : "");
}

std::string offset_attribute(std::uint64_t offset) {
  const std::string digits = std::to_string(offset);
  return " offset=\"" + digits + "\"" + std::string(kOffsetWidth - digits.size(), ' ');
}

void write_appended(std::ostream& os,
                    const std::function<std::string(const std::vector<std::uint64_t>& offsets)>& header,
                    const std::vector<AppendedArray>& arrays, bool compress, const std::string& footer) {
  std::vector<std::uint64_t> offsets(arrays.size(), 0);
  const std::string provisional = header(offsets);
  const std::streampos start = os.tellp();
  os.write(provisional.data(), static_cast<std::streamsize>(provisional.size()));
  std::uint64_t at = 0;
  for (std::size_t i = 0; i < arrays.size() && os; ++i) {
    offsets[i] = at;
    const std::vector<unsigned char> raw = raw_bytes(arrays[i]);
    if (compress) {
      at += write_compressed(os, raw);
    } else {
      put_u64s(os, {raw.size()});
      os.write(reinterpret_cast<const char*>(raw.data()), static_cast<std::streamsize>(raw.size()));
      at += sizeof(std::uint64_t) + raw.size();
    }
  }
  os << footer;
  const std::string final_header = header(offsets);
  if (final_header.size() != provisional.size())
    throw std::logic_error("write_appended: the VTK header changed length with its offsets");
  const std::streampos end = os.tellp();
  os.seekp(start);
  os.write(final_header.data(), static_cast<std::streamsize>(final_header.size()));
  os.seekp(end);
}

}  // namespace skred::vtk
