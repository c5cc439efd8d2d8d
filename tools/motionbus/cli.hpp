// Shared pieces of the motionbus CLI: JSON output, input parsing, options, command registry.
// Host code: uses the standard library freely (unlike include/).
#ifndef MOTIONBUS_TOOLS_CLI_HPP
#define MOTIONBUS_TOOLS_CLI_HPP

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cli {

/// One JSON object, fields in insertion order. Values are integers, strings, booleans or lists
/// of integers/strings.
class json_object {
 public:
  json_object& add(const std::string& key, std::int64_t value);
  json_object& add(const std::string& key, const std::string& value);
  json_object& add(const std::string& key, const char* value);
  json_object& add_bool(const std::string& key, bool value);
  json_object& add(const std::string& key, const std::vector<std::int64_t>& values);
  json_object& add(const std::string& key, const std::vector<std::string>& values);
  std::string str() const;

 private:
  std::vector<std::pair<std::string, std::string>> fields_;
};

std::string json_quote(const std::string& s);

/// Outcome of one input: ok with fields, or an error code (snake_case).
struct outcome {
  bool ok = false;
  json_object fields;
  std::string error;

  static outcome success(json_object f) { return outcome{true, std::move(f), {}}; }
  static outcome failure(std::string code) { return outcome{false, {}, std::move(code)}; }
};

/// "02 20 b4", "0220B4" or "0x02 0x20": hex bytes. Error code in `error` when invalid.
std::optional<std::vector<std::uint8_t>> parse_hex(const std::string& text, std::string& error);
/// "0101...": bits, first bit first. Spaces and underscores are ignored.
std::optional<std::vector<std::uint8_t>> parse_bits(const std::string& text, std::string& error);
/// Decimal or 0x-prefixed hex integer.
std::optional<std::uint64_t> parse_uint(const std::string& text);

/// `--name value` options and `--flag` switches after the positional arguments.
struct options {
  std::vector<std::string> positional;
  std::map<std::string, std::string> values;
  std::vector<std::string> flags;
  bool has(const std::string& name) const;
  std::optional<std::string> get(const std::string& name) const;
};
/// The number given with `--name` (parse_uint), `fallback` when absent; a usage error when it
/// is not a number or exceeds `max`.
std::uint64_t option_number(const options& opts, const std::string& name, std::uint64_t fallback,
                            std::uint64_t max);

/// Thrown (inside the tool only) for a usage error: exit status 2.
struct usage_error {
  std::string message;
};

/// Parses args[first..] as options; `with_value` names take a value, `switches` take none.
/// Anything else is a usage error.
options parse_options(const std::vector<std::string>& args, std::size_t first,
                      const std::vector<std::string>& with_value,
                      const std::vector<std::string>& switches);

/// A per-line handler: turns one input (hex, bits...) into an outcome.
using line_handler = outcome (*)(const std::string& input, const options& opts);
/// A no-input handler (encode).
using encode_handler = outcome (*)(const options& opts);

struct decoder {
  const char* protocol;
  const char* kind;
  line_handler handle;
  std::vector<std::string> value_options;
  std::vector<std::string> switch_options;
};

/// An encoder: `positional` arguments after the kind arrive in opts.positional.
struct encoder {
  const char* protocol;
  const char* kind;
  encode_handler handle;
  std::vector<std::string> value_options;
  std::vector<std::string> switch_options;
  std::size_t positional = 0;
};

/// `serve <name>` and `read <name>`: long-running or one-shot device I/O.
using service_handler = int (*)(const options& opts);
struct service {
  const char* name;
  service_handler run;
  std::vector<std::string> value_options;
  std::vector<std::string> switch_options;
};

/// Each protocol's file provides its entries; the registry gathers them.
struct protocol_entries {
  std::vector<decoder> decoders;
  std::vector<encoder> encoders;
  std::vector<service> emulators;  ///< serve <name>
  std::vector<service> devices;    ///< read <name>
};
protocol_entries tformat_entries();
protocol_entries modbus_entries();
protocol_entries sm_unit_entries();
protocol_entries biss_entries();

const std::vector<decoder>& decoders();
const std::vector<encoder>& encoders();
const std::vector<service>& emulators();
const std::vector<service>& devices();

/// Lower-case contiguous hex of bytes.
std::string to_hex(const std::uint8_t* data, std::size_t size);

/// Runs `handle` on `input`, or on each non-empty line of standard input when input is "-".
/// Prints one JSON object per input; returns 0 when all were valid, 1 otherwise.
int run_inputs(const std::string& input, const std::function<outcome(const std::string&)>& handle);

/// Prints one outcome as a JSON line.
void print(const outcome& o);

}  // namespace cli

#endif
