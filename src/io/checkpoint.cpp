#include "io/checkpoint.hpp"

#include <fmt/format.h>

#include <fstream>
#include <iterator>

#include "io/atomic_file.hpp"

namespace skred {

namespace {

constexpr std::size_t kHeaderSize = 8 + 4 + 4 + 8 + 8;  // magic, version, dimension, hash, size

template <class T>
T load(const std::string& bytes, std::size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

}  // namespace

std::uint64_t fnv1a64(const void* data, std::size_t n, std::uint64_t hash) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    hash ^= b[i];
    hash *= 0x100000001b3ull;  // FNV-1a 64-bit prime
  }
  return hash;
}

void write_checkpoint(const std::filesystem::path& file, const CheckpointKey& key,
                      const std::string& payload) {
  std::string head(kHeaderSize, '\0');
  const std::uint64_t size = payload.size();
  std::memcpy(head.data(), kCheckpointMagic, 8);
  std::memcpy(head.data() + 8, &kCheckpointVersion, 4);
  std::memcpy(head.data() + 12, &key.dimension, 4);
  std::memcpy(head.data() + 16, &key.scenario_hash, 8);
  std::memcpy(head.data() + 24, &size, 8);
  const std::uint64_t sum = fnv1a64(payload.data(), payload.size(), fnv1a64(head.data(), head.size()));
  write_file_atomically(file, [&](std::ostream& os) {
    os.write(head.data(), static_cast<std::streamsize>(head.size()));
    os.write(payload.data(), static_cast<std::streamsize>(payload.size()));
    os.write(reinterpret_cast<const char*>(&sum), sizeof sum);
  });
}

std::string read_checkpoint(const std::filesystem::path& file, const CheckpointKey& key) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw CheckpointError(fmt::format("cannot read checkpoint '{}'", name));
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kCheckpointMagic, 8) != 0)
    throw CheckpointError(fmt::format("'{}' is not a skred checkpoint (no SKREDCKP magic)", name));
  if (bytes.size() < kHeaderSize + 8)
    throw CheckpointError(fmt::format("checkpoint '{}' is truncated ({} bytes)", name, bytes.size()));
  const auto version = load<std::uint32_t>(bytes, 8);
  if (version != kCheckpointVersion)
    throw CheckpointError(fmt::format("checkpoint '{}' has format version {}; this skred reads version {}",
                                      name, version, kCheckpointVersion));
  const auto size = load<std::uint64_t>(bytes, 24);
  if (bytes.size() != kHeaderSize + size + 8)
    throw CheckpointError(fmt::format("checkpoint '{}' is truncated or damaged: {} bytes, its header says {}",
                                      name, bytes.size(), kHeaderSize + size + 8));
  if (fnv1a64(bytes.data(), bytes.size() - 8) != load<std::uint64_t>(bytes, bytes.size() - 8))
    throw CheckpointError(fmt::format("checkpoint '{}' is corrupt (checksum mismatch)", name));
  if (load<std::uint32_t>(bytes, 12) != key.dimension)
    throw CheckpointError(fmt::format("checkpoint '{}' is of a {}D run, not {}D", name,
                                      load<std::uint32_t>(bytes, 12), key.dimension));
  if (load<std::uint64_t>(bytes, 16) != key.scenario_hash)
    throw CheckpointError(
        fmt::format("checkpoint '{}' was written for another scenario "
                    "(the scenario text differs)",
                    name));
  return bytes.substr(kHeaderSize, size);
}

}  // namespace skred
