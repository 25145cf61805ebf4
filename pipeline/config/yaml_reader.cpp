#include "pipeline/config/yaml_reader.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/input_error.h"

namespace agv::pipeline {
namespace {

std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> parts;
  std::stringstream stream(key);
  std::string part;
  while (std::getline(stream, part, '.')) parts.push_back(part);
  return parts;
}

bool is_index(const std::string& part) {
  return !part.empty() && std::all_of(part.begin(), part.end(), ::isdigit);
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// "path.segments.3.length_m" -> "path.segments.N.length_m" for matching against known keys.
std::string generic(const std::string& key) {
  std::string out;
  for (const std::string& part : split_key(key)) {
    if (!out.empty()) out += '.';
    out += is_index(part) ? "N" : part;
  }
  return out;
}

}  // namespace

YAML::Node parse_yaml(const std::string& text, const std::string& source_name) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source_name + ": not valid YAML at line " + std::to_string(e.mark.line + 1) +
                     ": " + e.msg);
  }
}

YamlReader::YamlReader(YAML::Node root, std::string source_name)
    : root_(root), source_(std::move(source_name)) {
  if (!root_ || root_.IsNull()) root_ = YAML::Node(YAML::NodeType::Map);
  if (!root_.IsMap())
    throw InputError(source_ + ": expected a YAML mapping of keys at the top level");
}

std::string YamlReader::origin(const std::string& key) const {
  const auto it = overrides_.find(key);
  if (it != overrides_.end()) return it->second;
  // A group that only exists because an override created it ("controler" from
  // --set controler.ts_s=0.1) comes from that override.
  const auto created = created_groups_.find(key);
  return created != created_groups_.end() ? created->second : source_;
}

void YamlReader::fail(const std::string& key, const std::string& what) const {
  throw InputError(origin(key) + ": key '" + key + "': " + what);
}

void YamlReader::set_override(const std::string& dotted_key, const std::string& value_text) {
  const std::string option = "--set " + dotted_key + "=" + value_text;
  const std::vector<std::string> parts = split_key(dotted_key);
  if (parts.empty() || std::any_of(parts.begin(), parts.end(), [](auto& p) { return p.empty(); })) {
    throw InputError(option + ": expected key=value with a dotted key such as controller.ts_s=0.1");
  }
  YAML::Node value;
  try {
    value = YAML::Load(value_text);
  } catch (const YAML::Exception& e) {
    throw InputError(option + ": the value is not valid YAML (" + e.msg + ")");
  }
  // Walk down with fresh handles: yaml-cpp nodes are references, so assignment would rebind.
  std::vector<YAML::Node> chain{root_};
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node parent = chain.back();
    YAML::Node child;
    if (parent.IsSequence() && is_index(parts[i])) {
      const size_t index = std::stoul(parts[i]);
      if (index >= parent.size())
        throw InputError(option + ": index " + parts[i] + " is past the end of the sequence");
      child = parent[index];
    } else {
      if (!parent.IsMap() && !parent.IsNull())
        throw InputError(option + ": '" + parts[i] + "' is not a group of keys");
      child = parent[parts[i]];
      if (!child.IsDefined() || child.IsNull()) {
        parent[parts[i]] = YAML::Node(YAML::NodeType::Map);
        child = parent[parts[i]];
        std::string group;
        for (size_t j = 0; j <= i; ++j) group += (j ? "." : "") + parts[j];
        created_groups_.emplace(group, option);
      }
    }
    chain.push_back(child);
  }
  YAML::Node parent = chain.back();
  if (parent.IsSequence() && is_index(parts.back())) {
    const size_t index = std::stoul(parts.back());
    if (index >= parent.size()) throw InputError(option + ": index past the end of the sequence");
    parent[index] = value;
  } else {
    parent[parts.back()] = value;
  }
  overrides_[dotted_key] = option;
}

YAML::Node YamlReader::find(const std::string& key) const {
  std::vector<YAML::Node> chain{root_};
  for (const std::string& part : split_key(key)) {
    const YAML::Node parent = chain.back();
    if (parent.IsSequence() && is_index(part)) {
      const size_t index = std::stoul(part);
      if (index >= parent.size()) return YAML::Node(YAML::NodeType::Undefined);
      chain.push_back(parent[index]);
    } else if (parent.IsMap()) {
      const YAML::Node child = parent[part];
      if (!child.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
      chain.push_back(child);
    } else {
      return YAML::Node(YAML::NodeType::Undefined);
    }
  }
  return chain.back();
}

bool YamlReader::has(const std::string& key) const {
  const YAML::Node node = find(key);
  return node.IsDefined() && !node.IsNull();
}

double YamlReader::number(const std::string& key, double fallback, double min, double max) {
  known_.insert(key);
  const YAML::Node node = find(key);
  if (!node.IsDefined() || node.IsNull()) return fallback;
  if (!node.IsScalar()) fail(key, "expected a number");
  double value;
  const std::string& text = node.Scalar();
  if (text == ".nan" || text == ".NaN" || text == "nan" || text == "NaN" ||
      text.find("inf") != std::string::npos || text.find("Inf") != std::string::npos) {
    fail(key, "expected a finite number, got '" + text + "'");
  }
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    fail(key, "expected a number, got '" + text + "'");
  }
  if (!std::isfinite(value)) fail(key, "expected a finite number, got '" + text + "'");
  if (value < min || value > max) {
    std::ostringstream range;
    range << "value " << value << " is out of range [" << min << ", " << max << "]";
    fail(key, range.str());
  }
  return value;
}

double YamlReader::positive(const std::string& key, double fallback, double max) {
  const double value = number(key, fallback, -1e300, max);
  if (!(value > 0.0)) fail(key, "must be greater than 0");
  return value;
}

int YamlReader::integer(const std::string& key, int fallback, int min, int max) {
  known_.insert(key);
  const YAML::Node node = find(key);
  if (!node.IsDefined() || node.IsNull()) return fallback;
  long value;
  try {
    if (!node.IsScalar()) throw YAML::Exception(YAML::Mark::null_mark(), "");
    value = node.as<long>();
  } catch (const YAML::Exception&) {
    fail(key, "expected a whole number" +
                  (node.IsScalar() ? ", got '" + node.Scalar() + "'" : std::string()));
  }
  if (value < min || value > max) {
    fail(key, "value " + std::to_string(value) + " is out of range [" + std::to_string(min) + ", " +
                  std::to_string(max) + "]");
  }
  return static_cast<int>(value);
}

bool YamlReader::boolean(const std::string& key, bool fallback) {
  known_.insert(key);
  const YAML::Node node = find(key);
  if (!node.IsDefined() || node.IsNull()) return fallback;
  try {
    if (!node.IsScalar()) throw YAML::Exception(YAML::Mark::null_mark(), "");
    return node.as<bool>();
  } catch (const YAML::Exception&) {
    fail(key, "expected true or false");
  }
}

std::string YamlReader::text(const std::string& key, const std::string& fallback) {
  known_.insert(key);
  const YAML::Node node = find(key);
  if (!node.IsDefined() || node.IsNull()) return fallback;
  if (!node.IsScalar()) fail(key, "expected a single word or path");
  return node.Scalar();
}

std::string YamlReader::choice(const std::string& key, const std::string& fallback,
                               const std::vector<std::string>& allowed) {
  const std::string value = text(key, fallback);
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
    std::string list;
    for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(key, "'" + value + "' is not one of: " + list);
  }
  return value;
}

std::vector<double> YamlReader::numbers(const std::string& key, const std::vector<double>& fallback,
                                        size_t count, double min, double max) {
  known_.insert(key);
  const YAML::Node node = find(key);
  if (!node.IsDefined() || node.IsNull()) return fallback;
  if (!node.IsSequence() || node.size() != count) {
    fail(key, "expected a list of " + std::to_string(count) + " numbers, like [1, 2, 3]");
  }
  std::vector<double> values;
  for (size_t i = 0; i < count; ++i) {
    double value;
    try {
      value = node[i].as<double>();
    } catch (const YAML::Exception&) {
      fail(key, "element " + std::to_string(i) + " is not a number");
    }
    if (!std::isfinite(value) || value < min || value > max) {
      std::ostringstream range;
      range << "element " << i << " must be a finite number in [" << min << ", " << max << "]";
      fail(key, range.str());
    }
    values.push_back(value);
  }
  return values;
}

size_t YamlReader::sequence_size(const std::string& key) {
  known_.insert(key);
  const YAML::Node node = find(key);
  if (!node.IsDefined() || node.IsNull()) return 0;
  if (!node.IsSequence()) fail(key, "expected a list");
  return node.size();
}

std::vector<std::pair<std::string, std::string>> YamlReader::settings(const std::string& key) {
  known_.insert(key);
  const YAML::Node node = find(key);
  std::vector<std::pair<std::string, std::string>> pairs;
  if (!node.IsDefined() || node.IsNull()) return pairs;
  if (!node.IsMap()) fail(key, "expected a mapping of keys to values, like {duration_s: 10}");
  for (const auto& entry : node) {
    YAML::Emitter flow;
    flow.SetMapFormat(YAML::Flow);
    flow.SetSeqFormat(YAML::Flow);
    flow << entry.second;
    pairs.emplace_back(entry.first.Scalar(), flow.c_str());
  }
  return pairs;
}

void YamlReader::check_unused(const YAML::Node& node, const std::string& path) const {
  if (!node.IsMap()) return;
  for (const auto& entry : node) {
    const std::string key = path.empty() ? entry.first.Scalar() : path + "." + entry.first.Scalar();
    if (known_.count(key)) {
      if (entry.second.IsSequence()) {
        for (size_t i = 0; i < entry.second.size(); ++i)
          check_unused(entry.second[i], key + "." + std::to_string(i));
      }
      continue;
    }
    if (entry.second.IsMap()) {
      // A group is fine when some key below it is known; its unknown members are found below.
      const bool group_known = std::any_of(known_.begin(), known_.end(), [&](const std::string& k) {
        return generic(k).rfind(generic(key) + ".", 0) == 0;
      });
      if (group_known) {
        check_unused(entry.second, key);
        continue;
      }
    }
    // Closest known key, or known group of keys, at the same depth.
    std::set<std::string> candidates;
    const size_t depth = split_key(key).size();
    for (const std::string& k : known_) {
      const std::vector<std::string> parts = split_key(k);
      if (parts.size() < depth) continue;
      std::string prefix;
      for (size_t i = 0; i < depth; ++i) prefix += (i ? "." : "") + parts[i];
      candidates.insert(prefix);
    }
    std::string best;
    size_t best_distance = 1000;
    for (const std::string& k : candidates) {
      const size_t d = edit_distance(generic(key), generic(k));
      if (d < best_distance) {
        best_distance = d;
        best = k;
      }
    }
    std::string message = "unknown key";
    if (!best.empty() && best_distance <= std::max<size_t>(3, key.size() / 4))
      message += " (did you mean '" + best + "'?)";
    fail(key, message);
  }
}

void YamlReader::finish() const { check_unused(root_, ""); }

}  // namespace agv::pipeline
