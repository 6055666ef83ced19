#include "base/json_reader.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "base/input_limits.h"

namespace aoeval {

namespace {
std::string describe(const nlohmann::json& j) {
  std::string s = j.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

// Follows the parser's events to find a key given twice in one object: nlohmann keeps the last
// value silently, so a scene or spec with two "radius" keys would run with one the user may not
// have meant. Tracks the field path ("runs[1].grid.radius") for the message.
class DuplicateKeys {
 public:
  void see(nlohmann::json::parse_event_t event, const nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        frames_.push_back({event == E::object_start, {}, {}, 0});
        break;
      case E::key:
        frames_.back().key = parsed.get<std::string>();
        if (!frames_.back().keys.insert(frames_.back().key).second && found_.empty())
          found_ = path();
        break;
      case E::object_end:
      case E::array_end:
        frames_.pop_back();
        [[fallthrough]];
      case E::value:
        if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
        break;
    }
  }
  const std::string& found() const { return found_; }  // the path of the first duplicate, or ""
  // Where the parser is: the key (or index) path of the value it reads now, "" at the top.
  std::string path() const {
    std::string p;
    for (const Frame& f : frames_) {
      if (f.object)
        p.append(p.empty() ? "" : ".").append(f.key);
      else
        p.append("[").append(std::to_string(f.index)).append("]");
    }
    return p;
  }

 private:
  struct Frame {
    bool object;
    std::set<std::string> keys;
    std::string key;
    size_t index;
  };
  std::vector<Frame> frames_;
  std::string found_;
};
}  // namespace

JsonReader::JsonReader(const nlohmann::json& object, std::string file, std::string path)
    : object_(object), file_(std::move(file)), path_(std::move(path)) {
  if (!object_.is_object()) {
    throw InputError(file_ + ": " + (path_.empty() ? std::string("<root>") : path_) +
                     ": expected a JSON object, got " + describe(object_));
  }
}

std::string JsonReader::where(const std::string& key) const {
  if (path_.empty()) return key;
  if (key.empty()) return path_;
  return path_ + "." + key;
}

void JsonReader::fail(const std::string& key, const std::string& message) const {
  throw InputError(file_ + ": " + where(key) + ": " + message);
}

bool JsonReader::has(const std::string& key) const {
  return object_.contains(key);
}

const nlohmann::json& JsonReader::get(const std::string& key) {
  used_.insert(key);
  return object_.at(key);
}

const nlohmann::json& JsonReader::raw(const std::string& key) {
  if (!has(key)) fail(key, "required field is missing");
  return get(key);
}

double JsonReader::number(const std::string& key, double lo, double hi) {
  const auto& j = raw(key);
  if (!j.is_number()) fail(key, "expected a number, got " + describe(j));
  double v = j.get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream os;
    os << "value " << v << " is out of range [" << lo << ", " << hi << "]";
    fail(key, os.str());
  }
  return v;
}

double JsonReader::number(const std::string& key, double fallback, double lo, double hi) {
  return has(key) ? number(key, lo, hi) : fallback;
}

int64_t JsonReader::integer(const std::string& key, int64_t lo, int64_t hi) {
  const auto& j = raw(key);
  if (!j.is_number_integer()) fail(key, "expected an integer, got " + describe(j));
  int64_t v = j.get<int64_t>();
  if (v < lo || v > hi) {
    fail(key, "value " + std::to_string(v) + " is out of range [" + std::to_string(lo) + ", " +
                  std::to_string(hi) + "]");
  }
  return v;
}

int64_t JsonReader::integer(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) {
  return has(key) ? integer(key, lo, hi) : fallback;
}

bool JsonReader::boolean(const std::string& key, bool fallback) {
  if (!has(key)) return fallback;
  const auto& j = get(key);
  if (!j.is_boolean()) fail(key, "expected true or false, got " + describe(j));
  return j.get<bool>();
}

std::string JsonReader::string(const std::string& key) {
  const auto& j = raw(key);
  if (!j.is_string()) fail(key, "expected a string, got " + describe(j));
  return j.get<std::string>();
}

std::string JsonReader::string(const std::string& key, const std::string& fallback) {
  return has(key) ? string(key) : fallback;
}

std::string JsonReader::choice(const std::string& key, const std::string& fallback,
                               const std::vector<std::string>& choices) {
  std::string v = string(key, fallback);
  for (const auto& c : choices)
    if (c == v) return v;
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  fail(key, "\"" + v + "\" is not one of: " + list);
}

glm::vec3 JsonReader::vec3(const std::string& key) {
  const auto& j = raw(key);
  if (!j.is_array() || j.size() != 3) fail(key, "expected an array of 3 numbers");
  glm::vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!j[i].is_number()) fail(key, "expected an array of 3 numbers");
    double d = j[i].get<double>();
    if (!std::isfinite(d)) fail(key, "coordinates must be finite");
    if (std::fabs(d) > kMaxSceneCoordinate) {
      std::ostringstream os;
      os << "value " << d << " is out of range [" << -kMaxSceneCoordinate << ", "
         << kMaxSceneCoordinate << "] (aoeval works in 32-bit float)";
      fail(key, os.str());
    }
    v[i] = static_cast<float>(d);
  }
  return v;
}

std::array<double, 2> JsonReader::number_pair(const std::string& key,
                                              std::array<double, 2> fallback, double lo,
                                              double hi) {
  if (!has(key)) return fallback;
  const auto& j = raw(key);
  if (!j.is_array() || j.size() != 2 || !j[0].is_number() || !j[1].is_number())
    fail(key, "expected an array of 2 numbers");
  std::array<double, 2> v{j[0].get<double>(), j[1].get<double>()};
  for (double d : v) {
    if (!std::isfinite(d) || d < lo || d > hi)
      fail(key, "each value must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return v;
}

glm::vec3 JsonReader::vec3(const std::string& key, glm::vec3 fallback) {
  return has(key) ? vec3(key) : fallback;
}

JsonReader JsonReader::object(const std::string& key) {
  const auto& j = raw(key);
  if (!j.is_object()) fail(key, "expected an object, got " + describe(j));
  return JsonReader(j, file_, where(key));
}

std::optional<JsonReader> JsonReader::optional_object(const std::string& key) {
  if (!has(key)) return std::nullopt;
  return object(key);
}

std::vector<JsonReader> JsonReader::array_of_objects(const std::string& key, size_t min_count) {
  const auto& j = raw(key);
  if (!j.is_array()) fail(key, "expected an array, got " + describe(j));
  if (j.size() < min_count) {
    fail(key, "expected at least " + std::to_string(min_count) + " element(s), got " +
                  std::to_string(j.size()));
  }
  std::vector<JsonReader> out;
  for (size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_object()) fail(key + "[" + std::to_string(i) + "]", "expected an object");
    out.emplace_back(j[i], file_, where(key) + "[" + std::to_string(i) + "]");
  }
  return out;
}

void JsonReader::finish() const {
  for (auto it = object_.begin(); it != object_.end(); ++it) {
    if (!used_.count(it.key())) fail(it.key(), "unknown key");
  }
}

nlohmann::json parse_json_text(const std::string& text, const std::string& name) {
  if (text.size() > kMaxJsonBytes) {
    throw InputError(name + ": JSON file of " + std::to_string(text.size()) +
                     " bytes is larger than the limit of " + std::to_string(kMaxJsonBytes) +
                     " bytes");
  }
  // nlohmann's parser is iterative, but copies and dumps of a parsed value recurse: a document
  // nested 100,000 deep would overflow the stack later. The callback sees every value's depth while
  // parsing, so a too-deep document is rejected before anything walks it.
  bool too_deep = false;
  DuplicateKeys duplicates;
  const nlohmann::json::parser_callback_t depth_check =
      [&too_deep, &duplicates](int depth, nlohmann::json::parse_event_t event,
                               nlohmann::json& parsed) {
        if (depth > kMaxJsonDepth) too_deep = true;
        if (!too_deep) duplicates.see(event, parsed);
        return !too_deep;
      };
  // e.byte is the offset of the error; turn it into line:column for a human.
  auto position = [&text](size_t byte) {
    size_t line = 1, col = 1;
    for (size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    return std::to_string(line) + ":" + std::to_string(col);
  };
  nlohmann::json result;
  try {
    result = nlohmann::json::parse(text, depth_check);
  } catch (const nlohmann::json::parse_error& e) {
    // NaN, Infinity, a stray comma: the position, and the key whose value was being read.
    const std::string at = duplicates.path();
    throw InputError(name + ":" + position(e.byte) + ": invalid JSON" +
                     (at.empty() ? "" : " (at key " + at + ")"));
  } catch (const nlohmann::json::exception& e) {
    // out_of_range 406: a number such as 1e400 that no double holds.
    std::string what = e.what();
    if (auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
    const std::string at = duplicates.path();
    throw InputError(name + ": invalid JSON" + (at.empty() ? "" : " at key " + at) + ": " + what);
  }
  if (too_deep) {
    throw InputError(name + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                     " levels");
  }
  if (!duplicates.found().empty())
    throw InputError(name + ": " + duplicates.found() +
                     ": duplicate key (a key may appear once in an object)");
  return result;
}

nlohmann::json parse_json_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_json_text(ss.str(), path);
}

}  // namespace aoeval
