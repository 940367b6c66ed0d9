// Parses a LiSTA program's command line so that every program behaves alike:
// `--help` shows each option's default, the usage line names the program as
// users type it ("lista-bench volumetric", not a build path), and a usage
// error is one line, "<program>: error: <what> (see --help)", exit status 2.
#pragma once

#include <CLI/CLI.hpp>

#include <cctype>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

namespace lista::cli {

namespace detail {
// Defaults as the options hold them before parsing (flags have none to
// show), and no NaN or infinity for a number: a range check lets NaN through.
inline void prepare_options(CLI::App& app) {
  for (CLI::Option* o : app.get_options()) {
    if (o->get_expected_min() > 0 && o->get_default_str().empty()) {
      o->capture_default_str();
      if (o->get_default_str() == "[]") o->default_str("");  // an empty list says nothing
    }
    if (o->get_type_name().rfind("FLOAT", 0) == 0)
      o->check(CLI::Validator(
          [](std::string& v) {
            std::string lower;
            for (char c : v) lower += char(std::tolower(static_cast<unsigned char>(c)));
            return lower.find("nan") == std::string::npos && lower.find("inf") == std::string::npos
                       ? std::string()
                       : "must be a finite number, got " + v;
          },
          ""));
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) prepare_options(*sub);
}
}  // namespace detail

namespace detail {
// A bound as written by a person: 0.005, not 0.005000.
inline std::string plain_number(double v) {
  std::string s = std::to_string(v);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s;
}
}  // namespace detail

// A number no smaller than `lo`, said plainly (CLI11's NonNegativeNumber
// prints the largest double as its upper bound).
inline CLI::Validator at_least(double lo) {
  return CLI::Validator(
      [lo](std::string& v) {
        try {
          if (std::stod(v) >= lo) return std::string();
        } catch (const std::out_of_range&) {
          return "is out of range for a number, got " + v;  // 1e400 would become inf
        } catch (const std::exception&) {
          return std::string();  // not a number: the option's own conversion says so
        }
        return "must be at least " + detail::plain_number(lo) + ", got " + v;
      },
      "");
}

// A number in [lo, hi], said plainly (CLI11's Range prints 0.005000).
inline CLI::Validator between(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& v) {
        try {
          const double x = std::stod(v);
          if (x >= lo && x <= hi) return std::string();
        } catch (const std::out_of_range&) {
          return "is out of range for a number, got " + v;  // 1e400 would become inf, 1e-400 zero
        } catch (const std::exception&) {
          return std::string();  // not a number: the option's own conversion says so
        }
        return "must be between " + detail::plain_number(lo) + " and " + detail::plain_number(hi) + ", got " + v;
      },
      "");
}

// nullopt: parsed, go on. A value: the exit status to return now (0 after
// --help, 2 after a usage error, which is printed to stderr).
inline std::optional<int> parse_command_line(CLI::App& app, int argc, const char* const* argv,
                                             const std::string& program) {
  app.name(program);
  detail::prepare_options(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << program << ": error: " << e.what() << " (see --help)\n";
    return 2;
  }
  return std::nullopt;
}

}  // namespace lista::cli
