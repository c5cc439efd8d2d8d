// Shared pieces of the motionbus CLI: output records (text for people, JSON lines for programs,
// through nlohmann-json), input parsing, the command registry (the command line itself is parsed
// by CLI11: commands.cpp; each command's options are a struct bound to it: options.hpp). Host code:
// uses the standard library freely (unlike include/).
#ifndef MOTIONBUS_TOOLS_CLI_HPP
#define MOTIONBUS_TOOLS_CLI_HPP

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json_fwd.hpp>  // nlohmann/json.hpp where a JSON value is built or read
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <motionbus/core/errc.hpp>
#include <motionbus/core/result.hpp>

namespace CLI {
class App;
}  // namespace CLI

namespace cli {

/// The types record::add and record::hex take as integers.
template <class T>
constexpr bool is_recorded_integer =
    (std::is_integral_v<T> && !std::is_same_v<T, bool>) || std::is_enum_v<T>;

/// One output record: fields in order, each a JSON value (numbers stay numbers, with the field
/// names scripts already use) and the text a person reads (hex where engineers think in hex,
/// units where the profile has them).
class record {
 public:
  // Out of line (cli.cpp): the JSON object is held through a pointer so that this header needs
  // only json_fwd.hpp (json.hpp in every source of the CLI made each compile and each
  // clang-tidy run of them parse and walk it).
  record();
  ~record();
  record(const record& other);
  record& operator=(const record& other);
  record(record&& other) noexcept;
  record& operator=(record&& other) noexcept;

  /// An integer field of any integer or enumeration type (a bool is add_bool): JSON numbers are
  /// 64-bit, and every value the CLI records fits.
  template <class T, std::enable_if_t<is_recorded_integer<T>, int> = 0>
  record& add(const std::string& key, T value) {
    return add_integer(key, as_int64(value));
  }
  /// A number shown in hex in text ("0x1A", `digits` wide); a plain number in JSON.
  template <class T, std::enable_if_t<is_recorded_integer<T>, int> = 0>
  record& hex(const std::string& key, T value, int digits = 2) {
    return add_hex(key, as_int64(value), digits);
  }
  /// A number with its unit in text ("12.5 A"); a plain number in JSON.
  record& quantity(const std::string& key, double value, const std::string& unit);
  /// A measurement: {"value", "unit", "raw"} in JSON, "12.5 A" in text.
  record& measured(const std::string& key, double value, const std::string& unit, std::int64_t raw);
  record& add(const std::string& key, const std::string& value);
  record& add(const std::string& key, const char* value);
  record& add_bool(const std::string& key, bool value);
  record& add(const std::string& key, const std::vector<std::int64_t>& values);
  /// A list of integers of another type (counts: std::uint64_t).
  template <class T,
            std::enable_if_t<is_recorded_integer<T> && !std::is_same_v<T, std::int64_t>, int> = 0>
  record& add(const std::string& key, const std::vector<T>& values) {
    std::vector<std::int64_t> v;
    v.reserve(values.size());
    for (const T x : values) {
      v.push_back(as_int64(x));
    }
    return add(key, v);
  }
  record& add(const std::string& key, const std::vector<std::string>& values);
  /// A list of strings shown in text as `text`.
  record& add(const std::string& key, const std::vector<std::string>& values,
              const std::string& text);
  /// Raw bytes: lower-case contiguous hex in JSON (as the CLI always wrote them), spaced upper-case
  /// hex in text.
  record& bytes(const std::string& key, const std::uint8_t* data, std::size_t size);
  /// A field whose JSON value and text differ otherwise (e.g. alarm symbols, spelled out in text).
  record& add(const std::string& key, const nlohmann::ordered_json& value, const std::string& text);
  /// Appends the fields of `other` (after this record's own).
  record& append(const record& other);

  /// The fields as one JSON object, in order.
  const nlohmann::ordered_json& json() const;
  /// "key=value key=value ...", in order.
  std::string text() const;
  bool empty() const { return text_.empty(); }

 private:
  template <class T>
  static std::int64_t as_int64(T value) {
    if constexpr (std::is_enum_v<T>) {
      return as_int64(static_cast<std::underlying_type_t<T>>(value));
    } else {
      return static_cast<std::int64_t>(value);
    }
  }
  record& add_integer(const std::string& key, std::int64_t value);
  record& add_hex(const std::string& key, std::int64_t value, int digits);

  nlohmann::ordered_json& fields_json();  // json_, created at the first field

  std::unique_ptr<nlohmann::ordered_json> json_;  // null: no field yet (or moved from)
  std::vector<std::pair<std::string, std::string>> text_;
};

/// Outcome of one input: ok with fields, or an error code (snake_case) with its evidence
/// (expected and received values, where the failure was found).
struct outcome {
  bool ok = false;
  record fields;
  std::string error;
  record evidence;

  static outcome success(record f) { return outcome{true, std::move(f), {}, {}}; }
  static outcome failure(std::string code, record evidence = {}) {
    return outcome{false, {}, std::move(code), std::move(evidence)};
  }
};

/// The failure of a decode_result with its evidence: `expected` and `received` (in hex,
/// `digits` wide, in text) when the error carries them (a CRC computed and received, a CF or an
/// address that does not match the request).
template <class T, motionbus::input_unit Unit>
outcome failure_of(const motionbus::decode_result<T, Unit>& r, int digits = 2) {
  record e;
  if (r.expected() != r.received()) {
    e.hex("expected", r.expected(), digits).hex("received", r.received(), digits);
  }
  return outcome::failure(motionbus::to_string(r.error()), std::move(e));
}

/// Text (default) or one JSON object per line (--json).
enum class format : std::uint8_t { text, json };
/// The output format for this run (set once from the command line).
format output_format();
void set_output_format(format f);

/// Prints one outcome: "ok" or "FAIL <error>" then the fields, or one JSON object. `prefix`
/// fields (a time, a direction) come first.
void print(const outcome& o, const record& prefix = {});
/// Prints one summary or note record (never a frame): text "# key=value ...", or JSON.
void print_record(const record& r);

/// "02 20 b4", "0220B4" or "0x02 0x20": hex bytes. Error code in `error` when invalid.
std::optional<std::vector<std::uint8_t>> parse_hex(const std::string& text, std::string& error);
/// "0101...": bits, first bit first. Spaces and underscores are ignored.
std::optional<std::vector<std::uint8_t>> parse_bits(const std::string& text, std::string& error);
/// Decimal or 0x-prefixed hex integer.
std::optional<std::uint64_t> parse_uint(const std::string& text);

/// Thrown (inside the tool only) for a usage error: exit status 2.
struct usage_error {
  std::string message;
};

/// The value of a library builder's result (a request, a frame). When the library refuses the
/// arguments, a usage error that names its error code after `what` ("--slave 17: ..."):
/// nothing is sent and nothing is printed on standard output.
template <class T>
T built(const motionbus::result<T>& r, const std::string& what) {
  if (!r) {
    throw usage_error{what + " (the library refuses it: " + motionbus::to_string(r.error()) + ")"};
  }
  return r.value();
}

/// One input's outcome (a decoder's handler, its options bound).
using line_function = std::function<outcome(const std::string& input)>;

/// `decode <protocol> <kind> <input|->` or `crc <protocol> <input|->`: one outcome per input
/// line.
struct decoder {
  const char* group;  ///< "decode" or "crc"
  const char* protocol;
  const char* kind;  ///< "" where the protocol is the command (crc)
  const char* help;
  /// Binds the decoder's options (a struct: options.hpp) to its CLI11 app; returns the handler.
  std::function<line_function(CLI::App&)> bind;
  bool input = true;  ///< the input is required (else the options may carry it)
  /// What the input is, for --help ("the frame: <input_help>; - reads ...").
  const char* input_help = "hex bytes (\"02 20 b4\", \"0220B4\", \"0x02 0x20\")";
};

/// A command that takes no per-line input (`encode <protocol> <kind>`, `decode <protocol>
/// capture FILE`, `serve <name>`, `read <name>`, `monitor <name>`), its options a struct:
/// `bind` adds the options to the command's CLI11 app and returns what runs once they are
/// parsed.
struct typed_command {
  const char* group;  ///< "encode", "decode", "serve", "read", "monitor"
  const char* protocol;
  const char* kind;  ///< "" for serve/read/monitor
  const char* help;
  std::function<std::function<int()>(CLI::App&)> bind;
  const char* arguments = "";  ///< its positional arguments, for the listing ("<file>")
};

/// Each protocol's file provides its entries; the registry gathers them.
struct protocol_entries {
  std::vector<decoder> decoders;
  std::vector<typed_command> typed;
};
protocol_entries tformat_entries();
protocol_entries modbus_entries();
protocol_entries sm_unit_entries();
protocol_entries biss_entries();
protocol_entries crc_entries();
protocol_entries monitor_entries();
protocol_entries capture_entries();
protocol_entries gateway_entries();
protocol_entries serve_modbus_entries();

const std::vector<decoder>& decoders();
const std::vector<typed_command>& typed_commands();

/// Lower-case contiguous hex of bytes.
std::string to_hex(const std::uint8_t* data, std::size_t size);

/// Runs `handle` on `input`, or on each non-empty line of standard input when input is "-".
/// Prints one outcome per input; returns 0 when all were valid, 1 otherwise.
int run_inputs(const std::string& input, const std::function<outcome(const std::string&)>& handle);

/// Prints one outcome and returns its exit status (0 ok, 1 failed).
int finish(const outcome& o);

}  // namespace cli

#endif
