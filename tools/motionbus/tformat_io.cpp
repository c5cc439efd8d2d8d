// T-format records for the CLI (tformat_io.hpp): decode, read and the monitors print them.
#include "tformat_io.hpp"

#include <motionbus/tformat.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "cli.hpp"

namespace tf = motionbus::tformat;

namespace tformat_io {

namespace {
std::int64_t bit(bool b) {
  return b ? 1 : 0;
}

const char* alarm_name(tf::almc_bit a) {
  switch (a) {
    case tf::almc_bit::os: return "over-speed";
    case tf::almc_bit::fs: return "full-absolute status";
    case tf::almc_bit::ce: return "counting error";
    case tf::almc_bit::of: return "counter overflow";
    case tf::almc_bit::oh: return "over-heat";
    case tf::almc_bit::me: return "multi-turn error";
    case tf::almc_bit::be: return "battery error";
    case tf::almc_bit::ba: return "battery alarm";
  }
  return "unknown";
}
}  // namespace

cli::record response_record(const tf::response& r) {
  cli::record f;
  const tf::response_layout lay = r.layout();
  f.add("data_id", r.id);
  f.hex("cf", r.cf);
  if (lay.sf()) {
    f.hex("sf", r.sf);
    f.add("ea0", bit(r.ea0()))
        .add("ea1", bit(r.ea1()))
        .add("ca0", bit(r.ca0()))
        .add("ca1", bit(r.ca1()));
  }
  if (lay.abs()) {
    f.add("abs", r.abs);
  }
  if (lay.abm()) {
    f.add("abm", r.abm);
  }
  if (lay.enid()) {
    f.hex("enid", r.enid);
  }
  if (lay.almc()) {
    f.hex("almc", r.almc);
    // JSON: the symbols of the ALMC bits (the T-format specification, Table 3); text: their names
    std::vector<std::string> symbols;
    std::string text;
    for (tf::almc_bit a : tf::all_alarms) {
      if (tf::has_alarm(r.almc, a)) {
        symbols.emplace_back(tf::symbol(a));
        text += std::string(text.empty() ? "" : ", ") + tf::symbol(a) + " " + alarm_name(a);
      }
    }
    f.add("alarms", symbols, text.empty() ? "none" : "\"" + text + "\"");
  }
  if (lay.eeprom()) {
    f.hex("address", r.address);
    f.add("busy", bit(r.busy));
    f.hex("edf", r.edf);
  }
  f.hex("crc", r.crc);
  return f;
}

cli::record request_record(const tf::request& q) {
  cli::record f;
  f.add("data_id", q.id);
  f.hex("cf", q.cf);
  if (q.id == tf::data_id::eeprom_write || q.id == tf::data_id::eeprom_read) {
    f.hex("address", q.address);
    if (q.id == tf::data_id::eeprom_write) {
      f.hex("edf", q.edf);
    }
    f.hex("crc", q.crc);
  }
  return f;
}

}  // namespace tformat_io
