// One table per options struct that maps YAML keys onto its members.
// The same table loads YAML, applies "--set key=value" overrides, checks
// types and ranges, and dumps the effective values with their documentation,
// so the config file, the command line and the docs cannot drift apart.
//
//   ReconOptions options;
//   OptionSet set("recon");
//   set.add("lambda", options.lambda, "smoothness weight", 1e-4, 100.0);
//   set.apply_yaml(root["recon"], "my.yaml");   // throws ConfigError
//   options.validate();
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace YAML {
class Node;
}

namespace hos {

class OptionSet {
 public:
  // section is the top-level YAML key ("recon", "mvs", ...).
  explicit OptionSet(std::string section);

  const std::string& section() const { return section_; }

  // Keys may be dotted ("multigrid.max_levels"); in YAML they nest.
  void add(const std::string& key, bool& value, std::string doc);
  void add(const std::string& key, int& value, std::string doc, int min, int max);
  void add(const std::string& key, double& value, std::string doc, double min, double max);
  void add(const std::string& key, float& value, std::string doc, float min, float max);
  void add(const std::string& key, std::string& value, std::string doc);
  // A string restricted to a list of choices.
  void add_choice(const std::string& key, std::string& value, std::vector<std::string> choices,
                  std::string doc);
  // An enum parsed by name from a table; the error lists the valid names.
  template <typename Enum>
  void add_enum(const std::string& key, Enum& value,
                std::vector<std::pair<std::string, Enum>> table, std::string doc);

  // Applies a YAML map of this section (nested maps become dotted keys).
  // An unknown key throws ConfigError naming the key, source file and line and
  // the closest valid key; a bad value names the allowed type or range.
  void apply_yaml(const YAML::Node& node, const std::string& source);
  // Applies one "key=value" override (key without the section prefix).
  void apply_assignment(const std::string& key, const std::string& value,
                        const std::string& source = "command line");
  bool has_key(const std::string& key) const;

  // Current values as a nested YAML map.
  YAML::Node to_yaml() const;
  // "section:\n  key: value  # doc [range]\n" for config/default.yaml and --help.
  std::string documented_yaml() const;
  std::vector<std::string> keys() const;
  // Closest valid key by edit distance (for "did you mean").
  std::string closest_key(const std::string& key) const;

 private:
  struct Entry {
    std::string key;
    std::string doc;
    std::string allowed;  // "integer in [1, 64]", "one of: a, b"
    std::function<void(const std::string&)> parse;  // throws std::invalid_argument
    std::function<std::string()> print;
  };
  void add_entry(Entry entry);
  const Entry* find(const std::string& key) const;

  std::string section_;
  std::vector<Entry> entries_;
};

// Edit distance, for "did you mean" messages.
std::size_t edit_distance(const std::string& a, const std::string& b);

// Loads a YAML file; throws InputError with the file name and the parser's
// line and column on a syntax error.
YAML::Node load_yaml_file(const std::string& path);

template <typename Enum>
void OptionSet::add_enum(const std::string& key, Enum& value,
                         std::vector<std::pair<std::string, Enum>> table, std::string doc) {
  std::string allowed = "one of:";
  for (const auto& [name, e] : table) allowed += " " + name;
  Entry entry;
  entry.key = key;
  entry.doc = std::move(doc);
  entry.allowed = allowed;
  entry.parse = [&value, table, allowed](const std::string& text) {
    for (const auto& [name, e] : table) {
      if (name == text) {
        value = e;
        return;
      }
    }
    throw std::invalid_argument("must be " + allowed);
  };
  entry.print = [&value, table]() {
    for (const auto& [name, e] : table) {
      if (e == value) return name;
    }
    return std::string("?");
  };
  add_entry(std::move(entry));
}

}  // namespace hos
