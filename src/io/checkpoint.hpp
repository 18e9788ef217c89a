// Checkpoint files (OUTDIR/checkpoint.skc): a binary envelope around the state a run needs to
// continue bit for bit. Layout (host byte order):
//   magic "SKREDCKP" (8 bytes) | u32 format version | u32 dimension | u64 scenario hash |
//   u64 payload size | payload | u64 FNV-1a checksum of every byte before it
// The payload is written and read with ByteWriter / ByteReader (see run/checkpointing.cpp for
// what it holds). Files are written atomically (io/atomic_file.hpp).
#pragma once
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <istream>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace skred {

inline constexpr char kCheckpointMagic[8] = {'S', 'K', 'R', 'E', 'D', 'C', 'K', 'P'};
inline constexpr std::uint32_t kCheckpointVersion =
    14;  // 2: splitting, 3: contact, 4: friction and transfer work, 5: damping work,
         // 6: dilated continua (StageMeasures::dilated_*), 7: runout edges, 8: runout floor,
         // 9: the series' material speed, 10: the runout's toes, 11: the implicit integrator's
         // point acceleration and hoop stretch, 12: the prescribed velocities' forces,
         // 13: the hazard maps, 14: the points that moved in an earlier stage (the run's deposit)

// A checkpoint that cannot be used: truncated, corrupt, foreign, of another format version,
// dimension or scenario. The message names the file.
struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// 64-bit FNV-1a hash of n bytes, continuing from `hash`.
inline constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
std::uint64_t fnv1a64(const void* data, std::size_t n, std::uint64_t hash = kFnvOffset);

// What a checkpoint must match to be read: the dimension and the hash of the scenario text.
struct CheckpointKey {
  std::uint32_t dimension = 2;
  std::uint64_t scenario_hash = 0;
};

// Writes header, payload and checksum to `file` atomically. Throws std::runtime_error on I/O
// failure.
void write_checkpoint(const std::filesystem::path& file, const CheckpointKey& key,
                      const std::string& payload);
// Reads `file`, checks magic, version, size, checksum, dimension and scenario hash, and
// returns the payload. Throws CheckpointError naming the file and what is wrong.
std::string read_checkpoint(const std::filesystem::path& file, const CheckpointKey& key);

// Writes values into a stream: a(x) for arithmetic values, strings, optionals, pairs and
// vectors of them.
struct ByteWriter {
  std::ostream& os;
  template <class T>
  void operator()(const T& v) {
    if constexpr (std::is_arithmetic_v<T>) {
      os.write(reinterpret_cast<const char*>(&v), sizeof v);
    } else if constexpr (std::is_same_v<T, std::string>) {
      (*this)(static_cast<std::uint64_t>(v.size()));
      os.write(v.data(), static_cast<std::streamsize>(v.size()));
    } else if constexpr (requires { v.has_value(); }) {
      (*this)(static_cast<std::uint8_t>(v.has_value()));
      if (v) (*this)(*v);
    } else if constexpr (requires {
                           v.first;
                           v.second;
                         }) {
      (*this)(v.first);
      (*this)(v.second);
    } else {
      (*this)(static_cast<std::uint64_t>(v.size()));
      for (const auto& e : v) (*this)(e);
    }
  }
};

// Reads what ByteWriter wrote; throws CheckpointError("<what>: payload ends early") when the
// stream runs out.
struct ByteReader {
  std::istream& is;
  std::string what;  // the file, for messages
  void need(bool ok) const {
    if (!ok) throw CheckpointError(what + ": payload ends early or is inconsistent");
  }
  template <class T>
  void operator()(T& v) {
    if constexpr (std::is_arithmetic_v<T>) {
      is.read(reinterpret_cast<char*>(&v), sizeof v);
      need(static_cast<bool>(is));
    } else if constexpr (std::is_same_v<T, std::string>) {
      std::uint64_t n = 0;
      (*this)(n);
      need(n < (1u << 20));
      v.assign(n, '\0');
      is.read(v.data(), static_cast<std::streamsize>(n));
      need(static_cast<bool>(is));
    } else if constexpr (requires {
                           v.has_value();
                           v.reset();
                         }) {
      std::uint8_t has = 0;
      (*this)(has);
      v.reset();
      if (has) {
        typename T::value_type x{};
        (*this)(x);
        v = x;
      }
    } else if constexpr (requires {
                           v.first;
                           v.second;
                         }) {
      (*this)(v.first);
      (*this)(v.second);
    } else {
      std::uint64_t n = 0;
      (*this)(n);
      need(n < (1ull << 32));
      v.clear();
      v.resize(n);
      for (auto& e : v) (*this)(e);
    }
  }
};

}  // namespace skred
