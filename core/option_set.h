// One table per options struct that maps YAML keys onto its members.
// The same table loads YAML, applies "--set key=value" overrides, checks
// types and ranges, and dumps the effective values with their documentation,
// so the config file, the command line and the docs cannot drift apart.
//
//   ReconOptions options;
//   OptionSet set("recon");
//   set.add("lambda", options.lambda, "smoothness weight", 1e-4, 100.0);
//   set.add_flag("--lambda", "lambda");         // a stage executable's short flag
//   set.apply_yaml(root["recon"], "my.yaml");   // throws ConfigError
//   options.validate();                         // check_option_table + cross-option rules
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
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
  // A number in [min, max]; NaN and infinities are refused.
  template <typename Number>
  requires std::is_arithmetic_v<Number> &&(!std::is_same_v<Number, bool>)void add(
      const std::string& key, Number& value, std::string doc, Number min, Number max);
  // A number that is 0 (auto or off, as doc says) or in [min, max].
  template <typename Number>
  requires std::is_arithmetic_v<Number> &&(!std::is_same_v<Number, bool>)void add_zero_or(
      const std::string& key, Number& value, std::string doc, Number min, Number max);
  // An odd integer in [min, max] (the side of a window centred on a sample).
  void add_odd(const std::string& key, int& value, std::string doc, int min, int max);
  void add(const std::string& key, std::string& value, std::string doc);
  // A string restricted to a list of choices.
  void add_choice(const std::string& key, std::string& value, const std::vector<std::string>& choices, std::string doc);
  // An enum parsed by name from a table; the error lists the valid names.
  template <typename Enum>
  void add_enum(const std::string& key, Enum& value, std::vector<std::pair<std::string, Enum>> table, std::string doc);

  // Applies a YAML map of this section (nested maps become dotted keys).
  // An unknown key throws ConfigError naming the key, source file and line and
  // the closest valid key; a bad value names the allowed type or range.
  void apply_yaml(const YAML::Node& node, const std::string& source);
  // Applies one "key=value" override (key without the section prefix).
  void apply_assignment(const std::string& key, const std::string& value, const std::string& source = "command line");
  bool has_key(const std::string& key) const;

  // Throws ConfigError for the first option whose current value is outside
  // its table range or choices (values set in code rather than parsed).
  void check_values() const;

  // A stage executable's short flag for an option ("--resolution" for
  // "resolution"): it takes the option's value, or sets fixed_value when one
  // is given ("--no-trim" sets "trim.enabled" to "false"). Flags are applied
  // like --set, through the same parse and range check.
  struct Flag {
    std::string flag;
    std::string key;
    std::string fixed_value;  // empty: the flag takes a value
  };
  void add_flag(std::string flag, const std::string& key, std::string fixed_value = "");
  const std::vector<Flag>& flags() const { return flags_; }
  // The documentation of key, with its allowed values ("doc [range]").
  std::string documentation(const std::string& key) const;

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
    std::string allowed;                            // "integer in [1, 64]", "one of: a, b"
    std::function<void(const std::string&)> parse;  // throws std::invalid_argument
    std::function<std::string()> print;
    std::function<void()> check;  // throws std::invalid_argument when the current value is not allowed
  };
  void add_entry(Entry entry);
  const Entry* find(const std::string& key) const;
  // A number parsed like every other; `allowed` says in words which values
  // `is_allowed` accepts.
  template <typename Number, typename Predicate>
  void add_number(
      const std::string& key, Number& value, std::string doc, const std::string& allowed, Predicate is_allowed);
  // "an integer in [1, 64]", "a number in [0, 1]".
  template <typename Number>
  static std::string range_text(Number min, Number max);

  std::string section_;
  std::vector<Entry> entries_;
  std::vector<Flag> flags_;
};

// Checks every option of `options` against its table (register_options of
// its stage, found by argument-dependent lookup): the one place where ranges
// are written. Options::validate() calls it and adds only the rules that
// involve two options.
template <typename Options>
void check_option_table(const std::string& section, const Options& options) {
  Options copy = options;
  OptionSet set(section);
  register_options(set, copy);
  set.check_values();
}

// Parses a whole string as a number of type T (from_chars: no locale, no
// silent truncation; a leading '+' is allowed); nothing when the text is not
// exactly one number or does not fit T (e.g. "1e-7" for an int, "1e400" or
// "1e-400" for a double).
template <typename T>
std::optional<T> parse_number(const std::string& text);
extern template std::optional<int> parse_number<int>(const std::string&);
extern template std::optional<double> parse_number<double>(const std::string&);
extern template std::optional<float> parse_number<float>(const std::string&);
extern template std::optional<std::size_t> parse_number<std::size_t>(const std::string&);
extern template std::optional<std::uint32_t> parse_number<std::uint32_t>(const std::string&);
// Why parse_number<T> gave nothing for text: "is not a number", "is not an
// integer", "underflows: ..." (1e-400 for a double), "overflows: ...".
template <typename T>
std::string number_problem(const std::string& text);
extern template std::string number_problem<int>(const std::string&);
extern template std::string number_problem<double>(const std::string&);
extern template std::string number_problem<float>(const std::string&);
extern template std::string number_problem<std::size_t>(const std::string&);
extern template std::string number_problem<std::uint32_t>(const std::string&);
// The value as the config dump writes it (6 significant digits).
template <typename T>
std::string print_number(T value);
extern template std::string print_number<int>(int);
extern template std::string print_number<double>(double);
extern template std::string print_number<float>(float);
extern template std::string print_number<std::size_t>(std::size_t);
extern template std::string print_number<std::uint32_t>(std::uint32_t);

// Edit distance, for "did you mean" messages.
std::size_t edit_distance(const std::string& a, const std::string& b);

// Loads a YAML file; throws InputError when it cannot be opened, ConfigError
// with the file name and line on a syntax error, a key given twice in one
// map (naming both lines), a second document, or aliases that expand to more
// values than any config holds (kMaxConfigValues, option_set.cpp).
YAML::Node load_yaml_file(const std::string& path);

template <typename Number, typename Predicate>
void OptionSet::add_number(
    const std::string& key, Number& value, std::string doc, const std::string& allowed, Predicate is_allowed) {
  Entry entry;
  entry.key = key;
  entry.doc = std::move(doc);
  entry.allowed = allowed;
  entry.parse = [&value, is_allowed, allowed](const std::string& text) {
    const std::optional<Number> v = parse_number<Number>(text);
    if (!v) throw std::invalid_argument(number_problem<Number>(text) + "; must be " + allowed);
    if (!is_allowed(*v)) throw std::invalid_argument("must be " + allowed);
    value = *v;
  };
  entry.print = [&value]() { return print_number(value); };
  entry.check = [&value, is_allowed, allowed]() {
    if (!is_allowed(value)) throw std::invalid_argument("must be " + allowed);
  };
  add_entry(std::move(entry));
}

template <typename Number>
std::string OptionSet::range_text(Number min, Number max) {
  std::ostringstream range;
  range << (std::is_integral_v<Number> ? "an integer" : "a number") << " in [" << min << ", " << max << "]";
  return range.str();
}

template <typename Number>
requires std::is_arithmetic_v<Number> &&(!std::is_same_v<Number, bool>)void OptionSet::add(
    const std::string& key, Number& value, std::string doc, Number min, Number max) {
  // Written with ! so that NaN fails too.
  auto in_range = [min, max](Number v) { return !(v < min) && !(v > max) && v == v; };
  add_number(key, value, std::move(doc), range_text(min, max), in_range);
}

template <typename Number>
requires std::is_arithmetic_v<Number> &&(!std::is_same_v<Number, bool>)void OptionSet::add_zero_or(
    const std::string& key, Number& value, std::string doc, Number min, Number max) {
  auto zero_or_in_range = [min, max](Number v) { return v == 0 || (!(v < min) && !(v > max) && v == v); };
  add_number(key, value, std::move(doc), "0 or " + range_text(min, max), zero_or_in_range);
}

template <typename Enum>
void OptionSet::add_enum(const std::string& key,
                         Enum& value,
                         std::vector<std::pair<std::string, Enum>> table,
                         std::string doc) {
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
  entry.check = [&value, table, allowed]() {
    for (const auto& [name, e] : table) {
      if (e == value) return;
    }
    throw std::invalid_argument("must be " + allowed);
  };
  add_entry(std::move(entry));
}

}  // namespace hos
