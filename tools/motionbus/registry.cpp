// The registries of decoders, encoders, emulators and devices, gathered from each protocol's
// file, and the commands that use them.
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"

namespace cli {

namespace {

const std::vector<protocol_entries>& all_protocols() {
  static const std::vector<protocol_entries> list = {tformat_entries(), modbus_entries(),
                                                     sm_unit_entries(), biss_entries()};
  return list;
}

template <class T>
std::vector<T> gather(std::vector<T> protocol_entries::*member) {
  std::vector<T> out;
  for (const auto& p : all_protocols()) {
    out.insert(out.end(), (p.*member).begin(), (p.*member).end());
  }
  return out;
}

}  // namespace

const std::vector<decoder>& decoders() {
  static const std::vector<decoder> list = gather(&protocol_entries::decoders);
  return list;
}
const std::vector<encoder>& encoders() {
  static const std::vector<encoder> list = gather(&protocol_entries::encoders);
  return list;
}
const std::vector<service>& emulators() {
  static const std::vector<service> list = gather(&protocol_entries::emulators);
  return list;
}
const std::vector<service>& devices() {
  static const std::vector<service> list = gather(&protocol_entries::devices);
  return list;
}

}  // namespace cli

namespace {

template <class List>
std::string known_pairs(const List& list) {
  std::string out;
  for (const auto& e : list) {
    out += std::string(out.empty() ? "" : ", ") + e.protocol + " " + e.kind;
  }
  return out.empty() ? "none" : out;
}

std::string known_names(const std::vector<cli::service>& list) {
  std::string out;
  for (const auto& e : list) {
    out += std::string(out.empty() ? "" : ", ") + e.name;
  }
  return out.empty() ? "none" : out;
}

int run_service(const std::vector<std::string>& args, const std::vector<cli::service>& list,
                const char* what) {
  if (args.size() < 3) {
    throw cli::usage_error{std::string("usage: motionbus ") + args[1] + " <" + what +
                           "> --device PATH [options]"};
  }
  for (const auto& s : list) {
    if (args[2] == s.name) {
      const cli::options opts = cli::parse_options(args, 3, s.value_options, s.switch_options);
      return s.run(opts);
    }
  }
  throw cli::usage_error{"unknown " + std::string(what) + " '" + args[2] +
                         "' (available: " + known_names(list) + ")"};
}

}  // namespace

int command_decode(const std::vector<std::string>& args) {
  if (args.size() < 5) {
    throw cli::usage_error{"usage: motionbus decode <protocol> <kind> <input|-> [options]"};
  }
  for (const auto& d : cli::decoders()) {
    if (args[2] == d.protocol && args[3] == d.kind) {
      // No positional input when options come first (e.g. `decode biss csd --hex ...`): the
      // decoder takes its input from them.
      const bool options_only = args[4].size() > 2 && args[4].compare(0, 2, "--") == 0;
      const cli::options opts =
          cli::parse_options(args, options_only ? 4 : 5, d.value_options, d.switch_options);
      const cli::line_handler handle = d.handle;
      if (options_only) {
        const cli::outcome o = handle("", opts);
        cli::print(o);
        return o.ok ? 0 : 1;
      }
      return cli::run_inputs(args[4], [&](const std::string& in) { return handle(in, opts); });
    }
  }
  throw cli::usage_error{"unknown decoder '" + args[2] + " " + args[3] +
                         "' (available: " + known_pairs(cli::decoders()) + ")"};
}

int command_encode(const std::vector<std::string>& args) {
  if (args.size() < 4) {
    throw cli::usage_error{"usage: motionbus encode <protocol> <kind> [options]"};
  }
  for (const auto& e : cli::encoders()) {
    if (args[2] == e.protocol && args[3] == e.kind) {
      if (args.size() < 4 + e.positional) {
        throw cli::usage_error{"encode " + args[2] + " " + args[3] + " needs " +
                               std::to_string(e.positional) + " argument(s)"};
      }
      cli::options opts =
          cli::parse_options(args, 4 + e.positional, e.value_options, e.switch_options);
      opts.positional.assign(args.begin() + 4, args.begin() + static_cast<long>(4 + e.positional));
      const cli::outcome o = e.handle(opts);
      cli::print(o);
      return o.ok ? 0 : 1;
    }
  }
  throw cli::usage_error{"unknown encoder '" + args[2] + " " + args[3] +
                         "' (available: " + known_pairs(cli::encoders()) + ")"};
}

int command_serve(const std::vector<std::string>& args) {
  return run_service(args, cli::emulators(), "emulator");
}

int command_read(const std::vector<std::string>& args) {
  return run_service(args, cli::devices(), "device");
}
