// motionbus — T-format (Tamagawa Smart-Abs) frame vocabulary: Data IDs, the control field,
// status and alarm bits, and the layout of every request and response.
//
// Bytes are the fields' 8 data bits as a UART delivers them (bit 0 first on the wire); the
// start and delimiter bits of each 10-bit field are the line coding's business (line.hpp).
// Sources: TS5700N8500 specification §6.2–6.3, Tables 1 and 2; docs/tformat.md §2, §3, §7.
#ifndef MOTIONBUS_TFORMAT_FRAME_HPP
#define MOTIONBUS_TFORMAT_FRAME_HPP

#include <cstddef>
#include <cstdint>

namespace motionbus {
namespace tformat {

/// Data IDs (spec Table 1). The value is the 4-bit code cc3..cc0.
enum class data_id : std::uint8_t {
  read_abs = 0x0,           ///< ID0: single-turn position
  read_abm = 0x1,           ///< ID1: multi-turn count
  read_enid = 0x2,          ///< ID2: encoder ID
  read_all = 0x3,           ///< ID3: ABS, ENID, ABM, ALMC
  eeprom_write = 0x6,       ///< ID6: write one EEPROM byte
  reset_errors = 0x7,       ///< ID7: reset all latched errors (send 10 times)
  reset_single_turn = 0x8,  ///< ID8: zero the single-turn position (send 10 times)
  reset_multi_turn = 0xC,   ///< IDC: reset multi-turn count and errors (send 10 times)
  eeprom_read = 0xD,        ///< IDD: read one EEPROM byte
};

/// True for the nine Data IDs the spec defines.
inline constexpr std::uint8_t sync_code = 0x02;
inline constexpr std::uint8_t sync_mask = 0x07;

/// The control field byte for a 4-bit Data ID code: sync code, cc0..cc3 in bits 3..6, and the
/// parity cc4 = cc0 ^ cc1 ^ cc2 ^ cc3 in bit 7 (spec §6.3.1). ID0 0x02, ID3 0x1A, IDD 0xEA.
constexpr std::uint8_t control_field(std::uint8_t code) noexcept {
  const unsigned c = code & 0x0FU;
  const unsigned parity = (c ^ (c >> 1U) ^ (c >> 2U) ^ (c >> 3U)) & 1U;
  return static_cast<std::uint8_t>(sync_code | (c << 3U) | (parity << 7U));
}
constexpr std::uint8_t control_field(data_id id) noexcept {
  return control_field(static_cast<std::uint8_t>(id));
}

/// The control field of each 4-bit code, as a table (16 bytes of read-only data).
inline constexpr std::uint8_t control_fields[16] = {
    control_field(std::uint8_t{0x0}), control_field(std::uint8_t{0x1}),
    control_field(std::uint8_t{0x2}), control_field(std::uint8_t{0x3}),
    control_field(std::uint8_t{0x4}), control_field(std::uint8_t{0x5}),
    control_field(std::uint8_t{0x6}), control_field(std::uint8_t{0x7}),
    control_field(std::uint8_t{0x8}), control_field(std::uint8_t{0x9}),
    control_field(std::uint8_t{0xA}), control_field(std::uint8_t{0xB}),
    control_field(std::uint8_t{0xC}), control_field(std::uint8_t{0xD}),
    control_field(std::uint8_t{0xE}), control_field(std::uint8_t{0xF})};

/// Bit i set when code i is a defined Data ID (0, 1, 2, 3, 6, 7, 8, C, D).
inline constexpr std::uint16_t known_ids_mask = 0x31CF;

/// True for the Data IDs the protocol defines (0, 1, 2, 3, 6, 7, 8, C, D).
constexpr bool is_known(data_id id) noexcept {
  const auto code = static_cast<std::uint8_t>(id);
  return code < 16U && ((known_ids_mask >> code) & 1U) != 0U;
}

/// The control field of each defined code, and 0x00 for undefined codes: a byte whose code is
/// c != 0 cannot be 0x00, so `cf == valid_control_fields[code]` checks sync code, parity and
/// that the Data ID is defined in one comparison.
inline constexpr std::uint8_t valid_control_fields[16] = {control_fields[0x0],
                                                          control_fields[0x1],
                                                          control_fields[0x2],
                                                          control_fields[0x3],
                                                          0x00,
                                                          0x00,
                                                          control_fields[0x6],
                                                          control_fields[0x7],
                                                          control_fields[0x8],
                                                          0x00,
                                                          0x00,
                                                          0x00,
                                                          control_fields[0xC],
                                                          control_fields[0xD],
                                                          0x00,
                                                          0x00};

/// The 4-bit Data ID code in a control field byte (no checks).
constexpr std::uint8_t data_id_code(std::uint8_t cf) noexcept {
  return static_cast<std::uint8_t>((cf >> 3U) & 0x0FU);
}
constexpr bool sync_ok(std::uint8_t cf) noexcept {
  return (cf & sync_mask) == sync_code;
}
constexpr bool parity_ok(std::uint8_t cf) noexcept {
  return ((cf ^ control_fields[data_id_code(cf)]) & 0x80U) == 0U;
}

/// Status field bits (spec §6.3.2). Bits 0..3 are always 0.
namespace sf {
inline constexpr std::uint8_t reserved_mask = 0x0F;
inline constexpr std::uint8_t ea0 = 0x10;  ///< counting error
inline constexpr std::uint8_t ea1 = 0x20;  ///< OR of over-heat, multi-turn, battery error/alarm
inline constexpr std::uint8_t ca0 = 0x40;  ///< request parity error
inline constexpr std::uint8_t ca1 = 0x80;  ///< request delimiter error
}  // namespace sf

/// ALMC bits (spec Table 3).
enum class almc_bit : std::uint8_t {
  os = 0x01,  ///< over-speed (latched)
  fs = 0x02,  ///< full-absolute status (non-latched)
  ce = 0x04,  ///< counting error
  of = 0x08,  ///< counter overflow (latched)
  oh = 0x10,  ///< over-heat (latched)
  me = 0x20,  ///< multi-turn error (latched during power-on)
  be = 0x40,  ///< battery error (latched)
  ba = 0x80,  ///< battery alarm (non-latched)
};

/// Every alarm in ALMC bit order.
inline constexpr almc_bit all_alarms[8] = {almc_bit::os, almc_bit::fs, almc_bit::ce, almc_bit::of,
                                           almc_bit::oh, almc_bit::me, almc_bit::be, almc_bit::ba};

/// The spec's two-letter symbol of an alarm ("OS", "FS", ...).
constexpr const char* symbol(almc_bit a) noexcept {
  switch (a) {
    case almc_bit::os: return "OS";
    case almc_bit::fs: return "FS";
    case almc_bit::ce: return "CE";
    case almc_bit::of: return "OF";
    case almc_bit::oh: return "OH";
    case almc_bit::me: return "ME";
    case almc_bit::be: return "BE";
    case almc_bit::ba: return "BA";
  }
  return "??";
}

constexpr bool has_alarm(std::uint8_t almc, almc_bit a) noexcept {
  return (almc & static_cast<std::uint8_t>(a)) != 0U;
}

/// ea1 is the OR of OH, ME, BE and BA (spec §6.3.2); ea0 is CE.
inline constexpr std::uint8_t ea1_alarms = 0x10 | 0x20 | 0x40 | 0x80;

/// ADF: bits 0..6 EEPROM address, bit 7 busy (responses only).
inline constexpr std::uint8_t adf_address_mask = 0x7F;
inline constexpr std::uint8_t adf_busy = 0x80;
/// EEPROM address that selects the page when written.
inline constexpr std::uint8_t page_select_address = 127;

/// Longest frames, in fields (bytes).
inline constexpr std::size_t max_request_size = 4;
inline constexpr std::size_t max_response_size = 11;

/// The fields of a response after its CF, one bit each (wire order: SF, ABS, ENID, ABM, ALMC;
/// or ADF and EDF for the EEPROM frames, which have no SF).
namespace field_bit {
inline constexpr std::uint8_t abs = 0x01;
inline constexpr std::uint8_t enid = 0x02;
inline constexpr std::uint8_t abm = 0x04;
inline constexpr std::uint8_t almc = 0x08;
inline constexpr std::uint8_t eeprom = 0x10;
inline constexpr std::uint8_t read_all = abs | enid | abm | almc;  ///< ID3's fields
}  // namespace field_bit

/// Which fields a response carries (spec Table 2, Figures 1–3), and its size.
struct response_layout {
  std::uint8_t size;    ///< fields, CF and CRC included
  std::uint8_t fields;  ///< field_bit
  constexpr bool has(std::uint8_t field) const noexcept { return (fields & field) != 0U; }
  constexpr bool sf() const noexcept { return !has(field_bit::eeprom); }  ///< CF SF ...
  constexpr bool abs() const noexcept { return has(field_bit::abs); }     ///< ABS0..2
  constexpr bool enid() const noexcept { return has(field_bit::enid); }
  constexpr bool abm() const noexcept { return has(field_bit::abm); }  ///< ABM0..2
  constexpr bool almc() const noexcept { return has(field_bit::almc); }
  constexpr bool eeprom() const noexcept { return has(field_bit::eeprom); }  ///< CF ADF EDF CRC
};

/// The response layouts, indexed by Data ID code: the one statement of spec Table 2 in the
/// library. A code the encoder does not know is answered with ID3 data (spec §8.4), so its
/// entry is ID3's.
inline constexpr response_layout response_layouts[16] = {{6, field_bit::abs},        // 0 read ABS
                                                         {6, field_bit::abm},        // 1 read ABM
                                                         {4, field_bit::enid},       // 2 read ENID
                                                         {11, field_bit::read_all},  // 3 read all
                                                         {11, field_bit::read_all},  // 4 (as ID3)
                                                         {11, field_bit::read_all},  // 5 (as ID3)
                                                         {4, field_bit::eeprom},  // 6 EEPROM write
                                                         {6, field_bit::abs},     // 7 reset errors
                                                         {6, field_bit::abs},     // 8 reset ST
                                                         {11, field_bit::read_all},  // 9 (as ID3)
                                                         {11, field_bit::read_all},  // A (as ID3)
                                                         {11, field_bit::read_all},  // B (as ID3)
                                                         {6, field_bit::abs},        // C reset MT
                                                         {4, field_bit::eeprom},  // D EEPROM read
                                                         {11, field_bit::read_all},   // E (as ID3)
                                                         {11, field_bit::read_all}};  // F (as ID3)

/// The layout of the response to `id`.
constexpr response_layout layout_of(data_id id) noexcept {
  return response_layouts[static_cast<std::uint8_t>(id) & 0x0FU];
}

/// Size of a request frame: CF alone, CF ADF CRC (IDD), or CF ADF EDF CRC (ID6).
constexpr std::size_t request_size(data_id id) noexcept {
  return id == data_id::eeprom_write ? 4U : (id == data_id::eeprom_read ? 3U : 1U);
}

/// Single-turn resolution: valid bits of the 24-bit ABS field. The TS5700N8500 has 17 (ENID
/// 0x11); 23-bit (ENID 0x17) and 11-bit (ENID 0x0B) encoders exist.
struct resolution {
  std::uint8_t single_turn_bits = 17;  ///< 1..24
  std::uint8_t multi_turn_bits = 16;   ///< 1..24
};

/// The resolution an ENID announces, or `fallback` when the ENID is not a known code.
constexpr resolution resolution_for_enid(std::uint8_t enid, resolution fallback = {}) noexcept {
  switch (enid) {
    case 0x11: return {17, 16};
    case 0x17: return {23, 16};
    case 0x0B: return {11, 16};
    default: return fallback;
  }
}

/// Combined absolute position: turns above the single-turn bits.
constexpr std::uint64_t absolute_position(std::uint32_t abs, std::uint32_t abm,
                                          unsigned single_turn_bits = 17) noexcept {
  return (static_cast<std::uint64_t>(abm) << single_turn_bits) | abs;
}

/// A request as the encoder sees it.
struct request {
  data_id id = data_id::read_abs;
  std::uint8_t cf = control_field(data_id::read_abs);
  std::uint8_t address = 0;  ///< EEPROM address (ID6, IDD)
  std::uint8_t edf = 0;      ///< data to write (ID6)
  std::uint8_t crc = 0;      ///< received CRC (ID6, IDD)
};

/// A response as the master sees it; the fields present follow layout_of(id).
/// (The one-byte fields come first and together: a decoder fills them with few stores. The
/// decoders initialise them by position; the order is checked below the struct.)
struct response {
  data_id id = data_id::read_abs;
  std::uint8_t cf = control_field(data_id::read_abs);
  std::uint8_t sf = 0;       ///< status field (absent for ID6/IDD)
  std::uint8_t enid = 0;     ///< encoder ID
  std::uint8_t almc = 0;     ///< alarm bits
  std::uint8_t address = 0;  ///< EEPROM address (ID6/IDD)
  bool busy = false;         ///< EEPROM busy (ID6/IDD): EDF is then 0x00
  std::uint8_t edf = 0;      ///< EEPROM data (ID6/IDD)
  std::uint8_t crc = 0;
  std::uint32_t abs = 0;  ///< single-turn position
  std::uint32_t abm = 0;  ///< multi-turn count

  constexpr bool ea0() const noexcept { return (sf & sf::ea0) != 0U; }
  constexpr bool ea1() const noexcept { return (sf & sf::ea1) != 0U; }
  constexpr bool ca0() const noexcept { return (sf & sf::ca0) != 0U; }
  constexpr bool ca1() const noexcept { return (sf & sf::ca1) != 0U; }
  constexpr response_layout layout() const noexcept { return layout_of(id); }
};

// The decoders (codec.hpp) initialise a response by position: a reordering of its members is a
// compile error here rather than swapped values there.
static_assert(offsetof(response, id) < offsetof(response, cf) &&
                  offsetof(response, cf) < offsetof(response, sf) &&
                  offsetof(response, sf) < offsetof(response, enid) &&
                  offsetof(response, enid) < offsetof(response, almc) &&
                  offsetof(response, almc) < offsetof(response, address) &&
                  offsetof(response, address) < offsetof(response, busy) &&
                  offsetof(response, busy) < offsetof(response, edf) &&
                  offsetof(response, edf) < offsetof(response, crc) &&
                  offsetof(response, crc) < offsetof(response, abs) &&
                  offsetof(response, abs) < offsetof(response, abm),
              "response's members in the order the decoders' initialisers give them");

}  // namespace tformat
}  // namespace motionbus

#endif  // MOTIONBUS_TFORMAT_FRAME_HPP
