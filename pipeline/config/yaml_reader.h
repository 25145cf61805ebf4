#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace agv::pipeline {

// Parses YAML text; throws InputError naming `source_name` and the line of a syntax error.
YAML::Node parse_yaml(const std::string& text, const std::string& source_name);

// Reads typed values from a YAML tree by dotted key ("controller.ts_s"), checks each one
// (type, finiteness, range, allowed words) and remembers which keys were read, so that
// finish() can reject keys nobody asked for: a typo must not be silently ignored. Every error
// is an InputError naming the source file (or the --set option that gave the value) and the key.
class YamlReader {
 public:
  YamlReader(YAML::Node root, std::string source_name);

  // Replaces (or adds) the value at a dotted key with `value_text` parsed as YAML, as given on
  // the command line by --set key=value. Numeric parts index sequences
  // ("path.segments.0.length_m").
  void set_override(const std::string& dotted_key, const std::string& value_text);

  bool has(const std::string& key) const;
  double number(const std::string& key, double fallback, double min, double max);
  // A number that must be > 0 (strictly) and at most max.
  double positive(const std::string& key, double fallback, double max = 1e9);
  int integer(const std::string& key, int fallback, int min, int max);
  bool boolean(const std::string& key, bool fallback);
  std::string text(const std::string& key, const std::string& fallback);
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& allowed);
  // One of the words in `words`, as its enum value.
  template <typename Enum>
  Enum choice(const std::string& key, Enum fallback,
              const std::vector<std::pair<std::string, Enum>>& words) {
    std::string fallback_word;
    std::vector<std::string> allowed;
    for (const auto& [word, value] : words) {
      allowed.push_back(word);
      if (value == fallback) fallback_word = word;
    }
    const std::string chosen = choice(key, fallback_word, allowed);
    for (const auto& [word, value] : words)
      if (word == chosen) return value;
    return fallback;
  }
  std::vector<double> numbers(const std::string& key, const std::vector<double>& fallback,
                              size_t count, double min, double max);
  // Number of elements of a sequence of maps (0 when absent); its elements are read with
  // keys like "path.segments.2.length_m".
  size_t sequence_size(const std::string& key);
  // A mapping of free keys to YAML values (e.g. a suite's `set: {duration_s: 10}`), as
  // ("key", "value as flow YAML") pairs in file order; empty when absent. Its keys are not
  // checked here: they are checked where they are used.
  std::vector<std::pair<std::string, std::string>> settings(const std::string& key);

  // Throws InputError for the first key in the tree that no read asked for, suggesting the
  // closest known key.
  void finish() const;

  // Where a key's value came from, for messages: the file, or "--set key=value".
  std::string origin(const std::string& key) const;

 private:
  YAML::Node find(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  void check_unused(const YAML::Node& node, const std::string& path) const;

  YAML::Node root_;
  std::string source_;
  std::set<std::string> known_;                        // every key asked for
  std::map<std::string, std::string> overrides_;       // key -> "--set key=value"
  std::map<std::string, std::string> created_groups_;  // group made by an override -> its option
};

}  // namespace agv::pipeline
