// The templated number() binders of options.hpp, which need CLI11 whole (options.hpp names its
// types only, so that a command that binds no number compiles without it).
#ifndef MOTIONBUS_TOOLS_OPTIONS_BIND_HPP
#define MOTIONBUS_TOOLS_OPTIONS_BIND_HPP

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>

#include "options.hpp"

namespace cli {

template <class T>
CLI::Option* number(CLI::App& app, const std::string& name, T& field, std::uint64_t min,
                    std::uint64_t max) {
  CLI::Option* o = app.add_option_function<std::string>(
      "--" + name,
      [&field, name, min, max](const std::string& text) {
        field = static_cast<T>(number_in_range(name, text, min, max));
      },
      help_with_range(name, min, max));
  o->type_name(option_help(name).type)->default_str(std::to_string(field));
  return o;
}
/// A number with no default: empty when the option is absent.
template <class T>
CLI::Option* number(CLI::App& app, const std::string& name, std::optional<T>& field,
                    std::uint64_t min, std::uint64_t max) {
  CLI::Option* o = app.add_option_function<std::string>(
      "--" + name,
      [&field, name, min, max](const std::string& text) {
        field = static_cast<T>(number_in_range(name, text, min, max));
      },
      help_with_range(name, min, max));
  o->type_name(option_help(name).type);
  return o;
}
}  // namespace cli

#endif
