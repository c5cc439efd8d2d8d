// The decode/encode registries and the commands that use them. Each protocol adds its entries
// to the lists below.
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"

namespace cli {

const std::vector<decoder>& decoders() {
  static const std::vector<decoder> list = {};
  return list;
}

const std::vector<encoder>& encoders() {
  static const std::vector<encoder> list = {};
  return list;
}

}  // namespace cli

namespace {

std::string known_kinds(bool decoding) {
  std::string out;
  if (decoding) {
    for (const auto& d : cli::decoders()) {
      out += std::string(out.empty() ? "" : ", ") + d.protocol + " " + d.kind;
    }
  } else {
    for (const auto& e : cli::encoders()) {
      out += std::string(out.empty() ? "" : ", ") + e.protocol + " " + e.kind;
    }
  }
  return out.empty() ? "none yet" : out;
}

}  // namespace

int command_decode(const std::vector<std::string>& args) {
  if (args.size() < 5) {
    throw cli::usage_error{"usage: motionbus decode <protocol> <kind> <input|-> [options]"};
  }
  for (const auto& d : cli::decoders()) {
    if (args[2] == d.protocol && args[3] == d.kind) {
      const cli::options opts = cli::parse_options(args, 5, d.value_options, d.switch_options);
      const cli::line_handler handle = d.handle;
      return cli::run_inputs(args[4], [&](const std::string& in) { return handle(in, opts); });
    }
  }
  throw cli::usage_error{"unknown decoder '" + args[2] + " " + args[3] +
                         "' (available: " + known_kinds(true) + ")"};
}

int command_encode(const std::vector<std::string>& args) {
  if (args.size() < 4) {
    throw cli::usage_error{"usage: motionbus encode <protocol> <kind> [options]"};
  }
  for (const auto& e : cli::encoders()) {
    if (args[2] == e.protocol && args[3] == e.kind) {
      const cli::options opts = cli::parse_options(args, 4, e.value_options, e.switch_options);
      const cli::outcome o = e.handle(opts);
      cli::print(o);
      return o.ok ? 0 : 1;
    }
  }
  throw cli::usage_error{"unknown encoder '" + args[2] + " " + args[3] +
                         "' (available: " + known_kinds(false) + ")"};
}

int command_serve(const std::vector<std::string>& args) {
  throw cli::usage_error{"unknown emulator '" + (args.size() > 2 ? args[2] : std::string()) +
                         "' (none available yet)"};
}

int command_read(const std::vector<std::string>& args) {
  throw cli::usage_error{"unknown device '" + (args.size() > 2 ? args[2] : std::string()) +
                         "' (none available yet)"};
}
