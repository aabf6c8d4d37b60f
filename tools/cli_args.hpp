#pragma once
// A small command-line parser for the areamatch program: positional arguments, --flags and
// --options with values, numbers checked with messages that name the option. Usage errors are
// `UsageError`; the program turns them into exit status 2.

#include <areamatch/detail/nearest_name.hpp>
#include <areamatch/error.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace areamatch_cli {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// " (did you mean --NAME?)" for the known name nearest to `name`, when it is a typo away; else "".
inline std::string did_you_mean(const std::string& name, const std::set<std::string>& flags, const std::set<std::string>& options) {
  std::vector<std::string> known(flags.begin(), flags.end());
  known.insert(known.end(), options.begin(), options.end());
  const std::string best = areamatch::detail::nearest_name(name, known);
  return best.empty() ? std::string() : " (did you mean --" + best + "?)";
}

class Args {
 public:
  /// `flags` take no value; every other --name takes one (as `--name V` or `--name=V`).
  Args(const std::vector<std::string>& tokens, const std::set<std::string>& flags,
       const std::set<std::string>& options) {
    for (std::size_t i = 0; i < tokens.size(); ++i) {
      const std::string& t = tokens[i];
      if (t.size() > 2 && t.compare(0, 2, "--") == 0) {
        std::string name = t.substr(2), value;
        const auto eq = name.find('=');
        const bool inline_value = eq != std::string::npos;
        if (inline_value) {
          value = name.substr(eq + 1);
          name = name.substr(0, eq);
        }
        if (flags.count(name)) {
          if (inline_value) throw UsageError("--" + name + " takes no value");
          flags_.insert(name);
        } else if (options.count(name)) {
          if (!inline_value) {
            if (i + 1 >= tokens.size()) throw UsageError("--" + name + " needs a value");
            value = tokens[++i];
          }
          values_[name].push_back(value);
        } else {
          throw UsageError("unknown option --" + name + did_you_mean(name, flags, options));
        }
      } else if (t == "-h") {
        flags_.insert("help");
      } else {
        positional_.push_back(t);
      }
    }
  }

  bool flag(const std::string& name) const { return flags_.count(name) != 0; }
  const std::vector<std::string>& positional() const { return positional_; }

  /// The option's value; given more than once, the last.
  std::optional<std::string> text(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) return std::nullopt;
    return it->second.back();
  }

  /// Every value of an option that may be repeated (`--set A=1 --set B=2`), in order.
  std::vector<std::string> all(const std::string& name) const {
    auto it = values_.find(name);
    return it == values_.end() ? std::vector<std::string>{} : it->second;
  }

  /// A finite number, optionally required to be > 0 (`positive`) or ≥ 0.
  std::optional<double> number(const std::string& name, bool positive = false, bool non_negative = false) const {
    const auto t = text(name);
    if (!t) return std::nullopt;
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(t->c_str(), &end);
    if (t->empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
      throw UsageError("--" + name + " must be a number, got '" + *t + "'");
    }
    if (positive && !(v > 0.0)) throw UsageError("--" + name + " must be positive, got " + *t);
    if (non_negative && v < 0.0) throw UsageError("--" + name + " must not be negative, got " + *t);
    return v;
  }

  /// A number in [0, 1] (a share, a probability or a threshold on one).
  std::optional<double> fraction(const std::string& name) const {
    const auto v = number(name);
    if (v && !(*v >= 0.0 && *v <= 1.0)) throw UsageError("--" + name + " must be in [0, 1], got " + *text(name));
    return v;
  }

  std::optional<long long> integer(const std::string& name, long long min, long long max) const {
    const auto t = text(name);
    if (!t) return std::nullopt;
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(t->c_str(), &end, 10);
    if (t->empty() || *end != '\0' || errno == ERANGE || v < min || v > max) {
      throw UsageError("--" + name + " must be a whole number from " + std::to_string(min) + " to " +
                       std::to_string(max) + ", got '" + *t + "'");
    }
    return v;
  }

  void expect_positional(std::size_t count, const std::string& usage) const {
    if (positional_.size() != count) throw UsageError("expected " + std::to_string(count) + " argument(s): " + usage);
  }

 private:
  std::set<std::string> flags_;
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positional_;
};

}  // namespace areamatch_cli
