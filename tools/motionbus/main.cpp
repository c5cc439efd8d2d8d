// motionbus — command-line tool for engineers decoding captures and talking to devices.
//
//   motionbus crc <tformat|modbus|biss6|biss4> <input|->
//   motionbus decode <protocol> <kind> <input|-> [options]
//   motionbus encode <protocol> <kind> [options]
//   motionbus serve <emulator> --device PATH [options]
//   motionbus read <device> --device PATH [options]
//
// Output: one JSON object per input, always with "ok"; "error" holds a snake_case code when
// ok is false. Exit status: 0 all inputs valid, 1 some input invalid, 2 usage error.
#include <iostream>
#include <string>
#include <vector>

#include <motionbus/version.hpp>
#include "cli.hpp"
#include "commands.hpp"

namespace {

const char* const usage_text =
    "usage: motionbus <command> ...\n"
    "  crc <tformat|modbus|biss6|biss4> <input|->   CRC of hex bytes / a 0-1 bit string\n"
    "  decode <protocol> <kind> <input|-> [options] decode frames to JSON\n"
    "  encode <protocol> <kind> [options]           encode a frame to hex or bits\n"
    "  serve <emulator> --device PATH [options]     run a device emulator\n"
    "  read <device> --device PATH [options]        one transaction with a device\n"
    "  version                                      print the library version\n"
    "An input of '-' reads one input per line from standard input.\n";

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv, argv + argc);
  try {
    if (args.size() < 2 || args[1] == "--help" || args[1] == "-h" || args[1] == "help") {
      std::cerr << usage_text;
      return args.size() < 2 ? 2 : 0;
    }
    const std::string& command = args[1];
    if (command == "crc") {
      return command_crc(args);
    }
    if (command == "decode") {
      return command_decode(args);
    }
    if (command == "encode") {
      return command_encode(args);
    }
    if (command == "serve") {
      return command_serve(args);
    }
    if (command == "read") {
      return command_read(args);
    }
    if (command == "version") {
      std::cout << "{\"ok\":true,\"version\":\"" << MOTIONBUS_VERSION_MAJOR << '.'
                << MOTIONBUS_VERSION_MINOR << '.' << MOTIONBUS_VERSION_PATCH << "\"}\n";
      return 0;
    }
    throw cli::usage_error{"unknown command '" + command + "'"};
  } catch (const cli::usage_error& e) {
    std::cerr << "motionbus: " << e.message << '\n' << usage_text;
    return 2;
  }
}
