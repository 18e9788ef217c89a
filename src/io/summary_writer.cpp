#include "io/summary_writer.hpp"

#include <fmt/format.h>

#include <cmath>

#include "io/atomic_file.hpp"

namespace skred {

namespace {

// Length of the valid UTF-8 sequence starting at s[i], or 0 if it is not valid (overlong
// forms, surrogates and code points above U+10FFFF are rejected, as RFC 3629 requires).
std::size_t utf8_sequence_length(const std::string& s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  std::size_t len;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF)
    len = 2;
  else if (c >= 0xE0 && c <= 0xEF) {
    len = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    len = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (i + len > s.size()) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < len; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return len;
}

std::string json_number(double x) { return std::isfinite(x) ? fmt::format("{}", x) : std::string("null"); }

}  // namespace

std::string json_string(const std::string& s) {
  std::string r = "\"";
  r.reserve(s.size() + 2);
  for (std::size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    switch (c) {
      case '"': r += "\\\""; break;
      case '\\': r += "\\\\"; break;
      case '\b': r += "\\b"; break;
      case '\f': r += "\\f"; break;
      case '\n': r += "\\n"; break;
      case '\r': r += "\\r"; break;
      case '\t': r += "\\t"; break;
      default:
        if (c < 0x20) {
          r += fmt::format("\\u{:04x}", c);
        } else if (const std::size_t len = utf8_sequence_length(s, i); len > 0) {
          r.append(s, i, len);
          i += len;
          continue;
        } else {
          r += "\\ufffd";  // replacement character for a byte that is not valid UTF-8
        }
    }
    ++i;
  }
  r += '"';
  return r;
}

namespace {

// 3D runs: the runout along z, after runout_x_max.
std::string z_runout(const StageMeasures& m) {
  if (std::isnan(m.runout_z_min) && std::isnan(m.runout_z_max)) return "";
  return fmt::format(", \"runout_z_min\": {}, \"runout_z_max\": {}", json_number(m.runout_z_min),
                     json_number(m.runout_z_max));
}

std::string stages_json(const std::vector<StageMeasures>& stages) {
  std::string out;
  for (const StageMeasures& m : stages) {
    const auto num = [](double x) { return json_number(x); };
    out += fmt::format(
        "{}\n    {{\"name\": {}, \"start_time\": {}, \"end_time\": {}, \"steps\": {}, "
        "\"ended_by\": {},\n     \"runout\": {}, \"runout_x_min\": {}, \"runout_x_max\": {}, "
        "\"max_displacement\": {}, "
        "\"height_start\": {}, \"height_end\": {},\n     \"peak_mean_speed\": {}, "
        "\"peak_time\": {}, \"final_mean_speed\": {}, \"stop_time\": {}, \"rest_measure\": {},\n     "
        "\"gravity_work\": {}, \"kinetic_energy_change\": {}, \"strain_energy\": {}, "
        "\"plastic_dissipation\": {},\n     \"plastic_volume\": {}, \"plastic_points\": {},\n     "
        "\"dilated_points\": {}, \"dilated_first_time\": {}, \"dilated_last_time\": {}}}",
        out.empty() ? "" : ",", json_string(m.name), num(m.start_time), num(m.end_time), m.steps,
        json_string(m.ended_by), num(m.runout), num(m.runout_x_min), num(m.runout_x_max) + z_runout(m),
        num(m.max_displacement), num(m.height_start), num(m.height_end), num(m.peak_mean_speed),
        num(m.peak_time), num(m.final_mean_speed), m.stop_time ? num(*m.stop_time) : std::string("null"),
        json_string(m.rest_measure), num(m.gravity_work), num(m.kinetic_energy_change), num(m.strain_energy),
        num(m.plastic_dissipation), num(m.plastic_volume), m.plastic_points, m.dilated_points,
        m.dilated_first_time ? num(*m.dilated_first_time) : std::string("null"),
        m.dilated_last_time ? num(*m.dilated_last_time) : std::string("null"));
  }
  return stages.empty() ? out : out + "\n  ";
}

std::string phases_json(const std::vector<std::pair<std::string, double>>& phases) {
  std::string out;
  for (const auto& [name, seconds] : phases)
    out += fmt::format("{}\n    {}: {}", out.empty() ? "" : ",", json_string(name), json_number(seconds));
  return phases.empty() ? out : out + "\n  ";
}

// "velocity_transfer" with its parameters and "volumetric_strain", if the run set them.
std::string transfer_json(const Summary& s) {
  if (s.velocity_transfer.empty()) return "";
  std::string out = fmt::format("  \"velocity_transfer\": {},\n", json_string(s.velocity_transfer));
  if (s.velocity_transfer == "xpic")
    out += fmt::format("  \"xpic_order\": {},\n  \"xpic_period\": {},\n", s.xpic_order,
                       json_number(s.xpic_period));
  if (s.velocity_transfer == "flip")
    out += fmt::format("  \"pic_fraction\": {},\n", json_number(s.pic_fraction));
  return out + fmt::format("  \"volumetric_strain\": {},\n", json_string(s.volumetric_strain));
}

std::string limit_equilibrium_json(const Summary& s) {
  if (!std::isfinite(s.limit_equilibrium)) return "";
  const auto& c = s.slip_circle;
  return fmt::format("  \"limit_equilibrium\": {},\n  \"slip_circle\": [{}, {}, {}, {}, {}],\n",
                     json_number(s.limit_equilibrium), json_number(c[0]), json_number(c[1]),
                     json_number(c[2]), json_number(c[3]), json_number(c[4]));
}

std::string maps_json(const std::vector<std::string>& files) {
  if (files.empty()) return "";
  std::string out;
  for (const std::string& f : files) out += fmt::format("{}\n    {}", out.empty() ? "" : ",", json_string(f));
  return fmt::format("  \"maps\": [{}\n  ],\n", out);
}

std::string implicit_json(const Summary& s) {
  if (!s.implicit) return "";
  const Summary::Implicit& m = *s.implicit;
  std::string forces;
  for (const auto& [name, f] : m.forces) {
    std::string v;
    for (double x : f) v += (v.empty() ? "" : ", ") + json_number(x);
    forces += fmt::format("{}{}: [{}]", forces.empty() ? "" : ", ", json_string(name), v);
  }
  return fmt::format(
      "  \"implicit\": {{\"geometry\": {}, \"analysis\": {}, \"iteration\": {}, \"linear_solver\": {}, "
      "\"steps\": {}, \"iterations\": {}, \"factorisations\": {}, \"cut_steps\": {}, \"max_unknowns\": {}, "
      "\"max_factor_bytes\": {}, \"elastic_fallbacks\": {}, \"forces\": {{{}}}}},\n",
      json_string(m.geometry), json_string(m.analysis), json_string(m.iteration),
      json_string(m.linear_solver), m.steps, m.iterations, m.factorisations, m.cut_steps, m.max_unknowns,
      json_number(m.max_factor_bytes), m.elastic_fallbacks, forces);
}

std::string processes_json(const Summary& s) {
  if (s.processes <= 1) return {};
  const double mean = static_cast<double>(s.particles) / s.processes;
  return fmt::format(
      "  \"processes\": {{\"count\": {}, \"points_min\": {}, \"points_max\": {}, \"imbalance\": {}, "
      "\"setup_peak_bytes\": {}, \"rebalances\": {}, \"bytes_per_step\": {}, \"messages_per_step\": {}}},\n",
      s.processes, s.share_min, s.share_max, json_number(mean > 0 ? s.share_max / mean : NAN),
      json_number(s.setup_peak_bytes), s.rebalances, json_number(s.bytes_per_step),
      json_number(s.messages_per_step));
}

}  // namespace

void write_summary_json(const std::filesystem::path& file, const Summary& s) {
  const std::string text = fmt::format(
      "{{\n"
      "  \"status\": {},\n"
      "  \"message\": {},\n"
      "  \"steps\": {},\n"
      "  \"simulated_time\": {},\n"
      "  \"end_time\": {},\n"
      "  \"particles\": {},\n"
      "  \"cells\": {},\n{}"
      "  \"wall_seconds\": {},\n"
      "  \"particle_updates_per_second\": {},\n"
      "  \"memory\": {{\"peak_bytes\": {}, \"bytes_per_point\": {}}},\n"
      "  \"threads\": {},\n{}"
      "  \"scenario\": {},\n"
      "  \"interpolation\": {},\n"
      "  \"scheme\": {},\n{}{}"
      "  \"time_step\": {},\n{}"
      "  \"phase_seconds\": {{{}}},\n"
      "  \"stages\": [{}],\n{}"
      "  \"version\": {},\n"
      "  \"git_commit\": {}\n"
      "}}\n",
      json_string(s.status), json_string(s.message), s.steps, json_number(s.simulated_time),
      json_number(s.end_time), s.particles, s.cells,
      s.dimension == 2 ? std::string() : fmt::format("  \"dimension\": {},\n", s.dimension),
      json_number(s.wall_seconds), json_number(s.particle_updates_per_second),
      json_number(s.peak_memory_bytes), json_number(s.memory_bytes_per_point), s.threads, processes_json(s),
      json_string(s.scenario), json_string(s.interpolation), json_string(s.scheme), transfer_json(s),
      limit_equilibrium_json(s), json_number(s.time_step), implicit_json(s), phases_json(s.phase_seconds),
      stages_json(s.stages), maps_json(s.maps), json_string(s.version), json_string(s.git_commit));
  write_file_atomically(file, [&](std::ostream& os) { os << text; });
}

}  // namespace skred
