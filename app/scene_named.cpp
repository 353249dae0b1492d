// Named sections of a scene (scene_named.hpp): their keys and how each kind is read.
#include "scene_named.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "error.hpp"
#include "lists.hpp"
#include "scene_keys.hpp"

namespace brittle::scene_file {

const std::vector<NamedKey>& named_keys() {
  static const std::vector<NamedKey> keys = {
      {"notch", "start", "m", "x, y of the notch mouth, on the plate's outline"},
      {"notch", "direction", "", "dx, dy: direction from the mouth to the tip (normalised)"},
      {"notch", "length", "m", "> 0: distance from the mouth to the tip"},
      {"notch", "opening", "m", "> 0: width at the mouth"},
      {"notch", "shape", "", "wedge (closes to a point at the tip) | slot (constant width)"},
      {"boundary", "type", "", "fixed | velocity | traction"},
      {"boundary", "box", "m",
       "x_min, x_max, y_min, y_max, z_min, z_max of the reference position (inf allowed)"},
      {"boundary", "group", "", "name of a physical group of the .msh mesh (instead of box)"},
      {"boundary", "components", "", "fixed / velocity: which of x, y, z (default all)"},
      {"boundary", "velocity", "m/s", "vx, vy, vz (type = velocity)"},
      {"boundary", "traction", "Pa", "tx, ty, tz per unit reference area (type = traction)"},
      {"boundary", "history", "", "constant | ramp | table (default constant)"},
      {"boundary", "start", "s", ">= 0: the load is zero before this time (default 0)"},
      {"boundary", "ramp_time", "s", "> 0: history = ramp rises from 0 to 1 over this time"},
      {"boundary", "table", "", "history = table: t0, f0, t1, f1, ... with t ascending"},
      {"initial", "box", "m", "as boundary.box"},
      {"initial", "group", "", "as boundary.group"},
      {"initial", "velocity", "m/s", "vx, vy, vz at t = 0"},
      {"sensor", "position", "m", "x, y, z: the node nearest to it records (put it on a surface)"},
      {"sensor", "direction", "", "nx, ny, nz: the velocity component recorded (normalised)"},
  };
  return keys;
}

/// "boundary.top.traction" -> its kind, name and key, if it is a named-section key.
std::optional<std::array<std::string, 3>> split_named(const std::string& full) {
  const auto a = full.find('.');
  const auto b = full.rfind('.');
  if (a == std::string::npos || a == b || a == 0 || b == a + 1 || b + 1 == full.size())
    return std::nullopt;
  const std::string kind = full.substr(0, a);
  if (kind != "boundary" && kind != "initial" && kind != "notch" && kind != "sensor")
    return std::nullopt;
  return std::array<std::string, 3>{kind, full.substr(a + 1, b - a - 1), full.substr(b + 1)};
}

const NamedKey* find_named_key(const std::string& kind, const std::string& key) {
  for (const NamedKey& k : named_keys())
    if (k.kind == kind && k.key == key) return &k;
  return nullptr;
}

namespace {

/// Reads named sections into the scene, checking every value and the keys each type needs.
class NamedReader {
 public:
  explicit NamedReader(const NamedSection& s) : s_(s) {}
  bool has(const std::string& key) const { return s_.keys.count(key) > 0; }
  std::string where(const std::string& key) const {
    auto it = s_.keys.find(key);
    return (it == s_.keys.end() ? std::string("scene") : it->second.label) + ": " + s_.kind + "." +
           s_.name + "." + key;
  }
  [[noreturn]] void bad(const std::string& key, const std::string& why = "") const {
    const NamedKey* k = find_named_key(s_.kind, key);
    throw Error(error_message(where(key), " = '", s_.keys.at(key).value, "' ",
                              why.empty() ? "is not valid" : why, " (expected ",
                              k->unit.empty() ? "" : "in " + k->unit + ", ", k->expected, ")"));
  }
  void require(const std::string& key, const std::string& because) const {
    if (has(key)) return;
    const NamedKey* k = find_named_key(s_.kind, key);
    const std::string label = s_.keys.empty() ? "scene" : s_.keys.begin()->second.label;
    throw Error(error_message(label, ": [", s_.kind, ".", s_.name, "] needs ", key, " ", because,
                              " (expected ", k->expected, ")"));
  }
  std::string word(const std::string& key, std::initializer_list<const char*> allowed) const {
    const std::string v = lower(s_.keys.at(key).value);
    std::string words;
    for (const char* a : allowed) {
      if (v == a) return v;
      words += (words.empty() ? "" : ", ") + std::string(a);
    }
    bad(key, "is not one of: " + words + " (case does not matter)");
  }
  /// Numbers; `infinite` allows inf / -inf.
  std::vector<double> numbers(const std::string& key, std::size_t count,
                              bool infinite = false) const {
    std::vector<double> out;
    for (const std::string& t : list_words(s_.keys.at(key).value)) {
      if (infinite && (t == "inf" || t == "+inf" || t == "-inf")) {
        out.push_back(t == "-inf" ? -std::numeric_limits<double>::infinity()
                                  : std::numeric_limits<double>::infinity());
        continue;
      }
      const std::optional<double> v = parse_number(t);
      if (!v) bad(key, "is not a list of numbers");
      out.push_back(*v);
    }
    if (count > 0 && out.size() != count)
      bad(key, error_message("has ", out.size(), " numbers, not ", count));
    return out;
  }
  double number(const std::string& key) const { return numbers(key, 1)[0]; }
  RegionParams region() const {
    RegionParams r;
    if (has("box") && has("group"))
      throw Error(error_message(where("group"), ": give box or group, not both"));
    if (has("box")) {
      r.box = numbers("box", 6, true);
      for (int d = 0; d < 3; ++d)
        if (!(r.box[2 * d] <= r.box[2 * d + 1])) bad("box", "has a minimum above its maximum");
    } else if (has("group")) {
      r.group = s_.keys.at("group").value;
      if (r.group.empty()) bad("group", "is empty");
    } else {
      require("box", "or group: the region it acts on");
    }
    return r;
  }

 private:
  const NamedSection& s_;
};

}  // namespace

void read_named_sections(const std::vector<NamedSection>& sections, Scene& scene) {
  for (const NamedSection& s : sections) {
    NamedReader r(s);
    if (s.kind == "notch") {
      NotchParams n;
      n.name = s.name;
      for (const char* key : {"start", "direction", "length", "opening"})
        r.require(key, "(every notch has start, direction, length and opening)");
      const std::vector<double> start = r.numbers("start", 2), dir = r.numbers("direction", 2);
      const double norm = std::hypot(dir[0], dir[1]);
      if (!(norm > 0)) r.bad("direction", "is the zero vector");
      n.start[0] = start[0], n.start[1] = start[1];
      n.direction[0] = dir[0] / norm, n.direction[1] = dir[1] / norm;
      n.length = r.number("length");
      if (!(n.length > 0)) r.bad("length", "is out of range");
      n.opening = r.number("opening");
      if (!(n.opening > 0)) r.bad("opening", "is out of range");
      if (r.has("shape"))
        n.shape = r.word("shape", {"wedge", "slot"}) == "slot" ? NotchParams::Shape::slot
                                                               : NotchParams::Shape::wedge;
      scene.geometry.notches.push_back(n);
    } else if (s.kind == "sensor") {
      SensorParams p;
      p.name = s.name;
      for (const char* key : {"position", "direction"})
        r.require(key, "(a sensor has a position and a direction)");
      const std::vector<double> x = r.numbers("position", 3), n = r.numbers("direction", 3);
      const double norm = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(norm > 0) || !std::isfinite(norm)) r.bad("direction", "is not a direction");
      for (int d = 0; d < 3; ++d) p.position[d] = x[d], p.direction[d] = n[d] / norm;
      scene.sensors.push_back(p);
    } else if (s.kind == "initial") {
      InitialVelocityParams v;
      v.name = s.name;
      v.region = r.region();
      r.require("velocity", "(an [initial.NAME] section sets an initial velocity)");
      const std::vector<double> vel = r.numbers("velocity", 3);
      std::copy(vel.begin(), vel.end(), v.velocity);
      for (const char* key :
           {"type", "components", "traction", "history", "start", "ramp_time", "table"})
        if (r.has(key)) r.bad(key, "is not a key of [initial.NAME]");
      scene.initial.velocities.push_back(v);
    } else {
      BoundaryParams b;
      b.name = s.name;
      r.require("type", "");
      const std::string type = r.word("type", {"fixed", "velocity", "traction"});
      b.type = type == "fixed"      ? BoundaryParams::Type::fixed
               : type == "velocity" ? BoundaryParams::Type::velocity
                                    : BoundaryParams::Type::traction;
      b.region = r.region();
      if (b.type != BoundaryParams::Type::traction && r.has("components")) {
        std::fill(b.components, b.components + 3, false);
        const std::vector<std::string> words = list_words(s.keys.at("components").value);
        if (words.empty()) r.bad("components", "is empty");
        for (const std::string& w : words) {
          if (w != "x" && w != "y" && w != "z") r.bad("components", "names an unknown component");
          b.components[w[0] - 'x'] = true;
        }
      } else if (r.has("components")) {
        r.bad("components", "is not a key of a traction (the traction vector has all three)");
      }
      const std::string value_key = type == "traction" ? "traction" : "velocity";
      const std::string other_key = type == "traction" ? "velocity" : "traction";
      if (r.has(other_key)) r.bad(other_key, "does not go with type = " + type);
      if (type == "fixed") {
        if (r.has("velocity")) r.bad("velocity", "does not go with type = fixed");
        for (const char* key : {"history", "start", "ramp_time", "table"})
          if (r.has(key)) r.bad(key, "does not go with type = fixed");
      } else {
        r.require(value_key, "for type = " + type);
        const std::vector<double> v = r.numbers(value_key, 3);
        std::copy(v.begin(), v.end(), b.value);
        const std::string history =
            r.has("history") ? r.word("history", {"constant", "ramp", "table"}) : "constant";
        if (r.has("start")) {
          b.history.start = r.number("start");
          if (!(b.history.start >= 0)) r.bad("start", "is out of range");
        }
        if (history == "ramp") {
          b.history.kind = TimeHistory::Kind::ramp;
          r.require("ramp_time", "for history = ramp");
          b.history.ramp_time = r.number("ramp_time");
          if (!(b.history.ramp_time > 0)) r.bad("ramp_time", "is out of range");
        } else if (r.has("ramp_time")) {
          r.bad("ramp_time", "needs history = ramp");
        }
        if (history == "table") {
          b.history.kind = TimeHistory::Kind::table;
          r.require("table", "for history = table");
          b.history.table = r.numbers("table", 0);
          const auto& t = b.history.table;
          if (t.size() < 2 || t.size() % 2) r.bad("table", "is not a list of (t, value) pairs");
          for (std::size_t i = 2; i < t.size(); i += 2)
            if (!(t[i] > t[i - 2])) r.bad("table", "has times that do not ascend");
          if (r.has("start")) r.bad("start", "does not go with history = table (give t in it)");
        } else if (r.has("table")) {
          r.bad("table", "needs history = table");
        }
      }
      scene.boundaries.push_back(b);
    }
  }
}

}  // namespace brittle::scene_file
