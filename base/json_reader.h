// A validating reader over a JSON object, in the spirit of pbrt-v4's ParameterDictionary: every
// read is recorded, `finish()` reports the keys nobody asked for as errors, and every error names
// the file and the field path ("scene.json: objects[2].transform.scale: expected 3 numbers").
#pragma once

#include <array>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "base/errors.h"

namespace aoeval {

class JsonReader {
 public:
  // `file` is the file name used in messages; `path` is the field path of this object ("" = root).
  JsonReader(const nlohmann::json& object, std::string file, std::string path = "");

  bool has(const std::string& key) const;
  const nlohmann::json& raw(const std::string& key);  // marks the key as used; throws if absent

  double number(const std::string& key, double fallback, double lo, double hi);
  double number(const std::string& key, double lo, double hi);  // required
  int64_t integer(const std::string& key, int64_t fallback, int64_t lo, int64_t hi);
  int64_t integer(const std::string& key, int64_t lo, int64_t hi);  // required
  bool boolean(const std::string& key, bool fallback);
  std::string string(const std::string& key, const std::string& fallback);
  std::string string(const std::string& key);  // required
  // A string that must be one of `choices`.
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& choices);
  glm::vec3 vec3(const std::string& key, glm::vec3 fallback);
  glm::vec3 vec3(const std::string& key);  // required
  // An optional array of two numbers, each in [lo, hi] (a generator's "size": [w, d]).
  std::array<double, 2> number_pair(const std::string& key, std::array<double, 2> fallback,
                                    double lo, double hi);

  // Child readers: an object field, or each element of an array of objects.
  JsonReader object(const std::string& key);
  std::optional<JsonReader> optional_object(const std::string& key);
  std::vector<JsonReader> array_of_objects(const std::string& key, size_t min_count);

  // Throws InputError for the first key that was present but never read.
  void finish() const;

  // Throws InputError "file: path.key: message".
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  std::string where(const std::string& key) const;
  const std::string& file() const { return file_; }
  const nlohmann::json& json() const { return object_; }

 private:
  const nlohmann::json& get(const std::string& key);
  nlohmann::json object_;
  std::string file_;
  std::string path_;
  std::set<std::string> used_;
};

// Parses a JSON file; a syntax error becomes an InputError naming the file, line and column.
nlohmann::json parse_json_file(const std::string& path);
nlohmann::json parse_json_text(const std::string& text, const std::string& name);

}  // namespace aoeval
