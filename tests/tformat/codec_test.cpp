// T-format byte codec: spec vectors, every error, every prefix, every single-bit flip, round
// trips master encode -> encoder decode -> encoder reply -> master decode.
// Expected bytes are written out from the spec's tables (Table 1 bit patterns, Table 2 layouts)
// and CRCs computed here as the XOR of the fields (G = X^8 + 1), never by the codec under test.
#include "motionbus/tformat/codec.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "../support/prng.hpp"
#include "../support/tformat.hpp"
#include "motionbus/devices/ts5700n8500_emulator.hpp"

using namespace motionbus;
using namespace motionbus::tformat;

using namespace testutil;

TEST_CASE("encode_request: every Data ID, EEPROM frames, errors") {
  std::uint8_t out[4] = {};
  for (const auto& row : table1) {
    const auto n = encode_request(row.id, 5, 0x12, out);
    REQUIRE(n.ok());
    CHECK(out[0] == cf_from_table(row));
    CHECK(n.value() == request_size(row.id));
  }
  REQUIRE(encode_request(data_id::eeprom_write, 5, 0x12, out).value() == 4);
  CHECK(std::vector<std::uint8_t>(out, out + 4) == with_crc({0x32, 0x05, 0x12}));
  REQUIRE(encode_request(data_id::eeprom_read, 127, 0, out).value() == 3);
  CHECK(std::vector<std::uint8_t>(out, out + 3) == with_crc({0xEA, 0x7F}));

  CHECK(encode_request(static_cast<data_id>(4), out).error() == errc::tformat_unknown_data_id);
  CHECK(encode_request(data_id::eeprom_read, 128, 0, out).error() == errc::out_of_range);
  std::uint8_t small[2] = {0xAA, 0xAA};
  CHECK(encode_request(data_id::eeprom_read, 1, 0, small).error() == errc::buffer_too_small);
  CHECK(small[0] == 0xAA);  // nothing written
  CHECK(encode_request(data_id::read_abs, mutable_byte_view{}).error() == errc::buffer_too_small);
}

TEST_CASE("decode_response: spec layouts and values") {
  const auto id0 = with_crc({0x02, 0x00, 0x40, 0xE2, 0x01});
  auto r = decode_response(view(id0));
  REQUIRE(r.is_complete());
  CHECK(r.consumed() == 6);
  CHECK(r->id == data_id::read_abs);
  CHECK(r->abs == 123456);
  CHECK(r->crc == xor_of({0x02, 0x00, 0x40, 0xE2, 0x01}));

  const auto id3 = with_crc({0x1A, 0xF0, 0xFF, 0xFF, 0x01, 0x11, 0xFF, 0xFF, 0x00, 0xD4});
  r = decode_response(view(id3));
  REQUIRE(r.is_complete());
  CHECK(r->id == data_id::read_all);
  CHECK(r->abs == 0x1FFFF);
  CHECK(r->enid == 0x11);
  CHECK(r->abm == 0xFFFF);
  CHECK(r->almc == 0xD4);
  CHECK(r->ea0());
  CHECK(r->ea1());
  CHECK(r->ca0());
  CHECK(r->ca1());
  CHECK(has_alarm(r->almc, almc_bit::ce));
  CHECK(has_alarm(r->almc, almc_bit::oh));
  CHECK(has_alarm(r->almc, almc_bit::be));
  CHECK(has_alarm(r->almc, almc_bit::ba));
  CHECK(!has_alarm(r->almc, almc_bit::os));

  const auto enid = with_crc({0x92, 0x00, 0x11});
  r = decode_response(view(enid));
  REQUIRE(r.is_complete());
  CHECK(r->enid == 0x11);
  CHECK(r.consumed() == 4);

  const auto busy = with_crc({0xEA, 0x85, 0x00});
  r = decode_response(view(busy));
  REQUIRE(r.is_complete());  // a busy EEPROM is state, not corruption
  CHECK(r->busy);
  CHECK(r->address == 5);
  CHECK(r->edf == 0);
}

TEST_CASE("decode_response: every documented error") {
  // truncated (exact-frame form) and wrong length
  const auto id0 = with_crc({0x02, 0x00, 0x40, 0xE2, 0x01});
  CHECK(decode_response_frame(view(id0).first(5)).error() == errc::truncated);
  auto longer = id0;
  longer.push_back(0x00);
  CHECK(decode_response_frame(view(longer)).error() == errc::tformat_length);
  CHECK(decode_response_frame(view(id0)).is_complete());
  // sync code, parity, unknown Data ID
  CHECK(decode_response(view(with_crc({0x03, 0x00, 0, 0, 0}))).error() == errc::tformat_sync_code);
  CHECK(decode_response(view(with_crc({0x82, 0x00, 0, 0, 0}))).error() == errc::tformat_parity);
  const std::uint8_t id4_cf = control_field(std::uint8_t{4});
  CHECK(decode_response(view(with_crc({id4_cf, 0, 0, 0, 0}))).error() ==
        errc::tformat_unknown_data_id);
  // CRC mismatch, with evidence
  // (a std::array: g++ 12's -Wnull-dereference misreads an inlined copy of the vector)
  std::array<std::uint8_t, 6> bad_crc{};
  std::copy(id0.begin(), id0.end(), bad_crc.begin());
  bad_crc[5] ^= 0x01;
  const auto c = decode_response(byte_view(bad_crc.data(), bad_crc.size()));
  CHECK(c.error() == errc::crc_mismatch);
  CHECK(c.expected() == id0[5]);
  CHECK(c.received() == bad_crc[5]);
  CHECK(c.consumed() == 1);
  // reserved SF bits
  CHECK(decode_response(view(with_crc({0x02, 0x01, 0, 0, 0}))).error() == errc::reserved_bits);
  // ABS above 17 bits / ABM above 16 bits
  CHECK(decode_response(view(with_crc({0x02, 0x00, 0, 0, 0x02}))).error() == errc::out_of_range);
  CHECK(decode_response(view(with_crc({0x8A, 0x00, 0, 0, 0x01}))).error() == errc::out_of_range);
  decode_options lax;
  lax.check_unused_bits = false;
  CHECK(decode_response(view(with_crc({0x02, 0x00, 0, 0, 0x02})), lax).value().abs == 0x20000);
}

TEST_CASE("decode_response_for: CF, address, data, communication alarm") {
  std::uint8_t req[4] = {};
  REQUIRE(encode_request(data_id::read_abs, req).ok());
  CHECK(decode_response_for(byte_view(req, 1), view(with_crc({0x02, 0, 1, 0, 0}))).is_complete());
  const auto cf = decode_response_for(byte_view(req, 1), view(with_crc({0x8A, 0, 1, 0, 0})));
  CHECK(cf.error() == errc::tformat_cf_mismatch);
  CHECK(cf.expected() == 0x02);
  CHECK(cf.received() == 0x8A);
  CHECK(cf.consumed() == 6);
  // The encoder saw a parity error: ID3 data with ca0, whatever was asked.
  const auto alarm3 = with_crc({0x1A, 0x40, 0, 0, 0, 0x11, 0, 0, 0, 0});
  CHECK(decode_response_for(byte_view(req, 1), view(alarm3)).error() ==
        errc::tformat_communication_alarm);
  const auto alarm3b = with_crc({0x1A, 0x80, 0, 0, 0, 0x11, 0, 0, 0, 0});
  CHECK(decode_response_for(byte_view(req, 1), view(alarm3b)).error() ==
        errc::tformat_communication_alarm);

  REQUIRE(encode_request(data_id::eeprom_read, 9, 0, req).ok());
  CHECK(decode_response_for(byte_view(req, 3), view(with_crc({0xEA, 0x09, 0x42}))).value().edf ==
        0x42);
  CHECK(decode_response_for(byte_view(req, 3), view(with_crc({0xEA, 0x08, 0x42}))).error() ==
        errc::tformat_address_mismatch);
  CHECK(decode_response_for(byte_view(req, 3), view(with_crc({0xEA, 0x89, 0x00}))).value().busy);

  REQUIRE(encode_request(data_id::eeprom_write, 9, 0x55, req).ok());
  CHECK(decode_response_for(byte_view(req, 4), view(with_crc({0x32, 0x09, 0x55}))).is_complete());
  CHECK(decode_response_for(byte_view(req, 4), view(with_crc({0x32, 0x09, 0x54}))).error() ==
        errc::tformat_data_mismatch);
  CHECK(decode_response_for(byte_view(req, 4), view(with_crc({0x32, 0x89, 0x00}))).is_complete());

  // malformed request frames
  CHECK(decode_response_for(byte_view{}, view(with_crc({0x02, 0, 1, 0, 0}))).error() ==
        errc::invalid_argument);
  CHECK(decode_response_for(byte_view(req, 2), view(with_crc({0x32, 0x09, 0x55}))).error() ==
        errc::invalid_argument);
}

TEST_CASE("every prefix of every valid response needs more input; the whole frame decodes") {
  for (const auto& frame : valid_responses()) {
    for (std::size_t n = 0; n < frame.size(); ++n) {
      const auto r = decode_response(view(frame).first(n));
      CHECK(r.is_incomplete());
      CHECK(r.needed() >= 1);
      if (n > 0) {
        CHECK(r.needed() == frame.size() - n);
      }
    }
    const auto r = decode_response(view(frame));
    REQUIRE(r.is_complete());
    CHECK(r.consumed() == frame.size());
  }
}

TEST_CASE("every single-bit flip of every valid response is detected") {
  for (const auto& frame : valid_responses()) {
    for (std::size_t byte = 0; byte < frame.size(); ++byte) {
      for (unsigned bit = 0; bit < 8; ++bit) {
        auto bad = frame;
        bad[byte] = static_cast<std::uint8_t>(bad[byte] ^ (1U << bit));
        const auto r = decode_response_frame(view(bad));
        CAPTURE(byte);
        CAPTURE(bit);
        CHECK(r.is_failed());
      }
    }
  }
}

TEST_CASE("decode_request (encoder side): every ID, EEPROM CRC and busy bit") {
  for (const auto& row : table1) {
    std::uint8_t out[4] = {};
    const auto n = encode_request(row.id, 100, 0xA5, out).value();
    const auto q = decode_request(byte_view(out, n));
    REQUIRE(q.is_complete());
    CHECK(q->id == row.id);
    CHECK(q.consumed() == n);
    if (row.id == data_id::eeprom_write) {
      CHECK(q->address == 100);
      CHECK(q->edf == 0xA5);
    }
    for (std::size_t k = 1; k < n; ++k) {
      CHECK(decode_request(byte_view(out, k)).is_incomplete());
    }
  }
  CHECK(decode_request(byte_view{}).is_incomplete());
  const std::uint8_t bad_sync[] = {0x00};
  CHECK(decode_request(bad_sync).error() == errc::tformat_sync_code);
  const std::uint8_t bad_parity[] = {0x82};
  CHECK(decode_request(bad_parity).error() == errc::tformat_parity);
  const std::uint8_t unknown[] = {control_field(std::uint8_t{0xF})};
  CHECK(decode_request(unknown).error() == errc::tformat_unknown_data_id);
  auto bad_crc = with_crc({0xEA, 0x05});
  bad_crc[2] ^= 0x10;
  CHECK(decode_request(view(bad_crc)).error() == errc::crc_mismatch);
  CHECK(decode_request(view(with_crc({0xEA, 0x85}))).error() == errc::reserved_bits);
}

TEST_CASE("encode_response (encoder side) matches spec layouts and refuses bad values") {
  response r;
  r.id = data_id::read_all;
  r.sf = 0x20;
  r.abs = 0x1FFFF;
  r.enid = 0x11;
  r.abm = 0xFFFF;
  r.almc = 0xC0;
  std::uint8_t out[11] = {};
  REQUIRE(encode_response(r, out).value() == 11);
  CHECK(std::vector<std::uint8_t>(out, out + 11) ==
        with_crc({0x1A, 0x20, 0xFF, 0xFF, 0x01, 0x11, 0xFF, 0xFF, 0x00, 0xC0}));
  r.sf = 0x01;
  CHECK(encode_response(r, out).error() == errc::reserved_bits);
  r.sf = 0;
  r.abs = 1U << 24U;
  CHECK(encode_response(r, out).error() == errc::out_of_range);
  r.abs = 0;
  std::uint8_t small[10] = {};
  CHECK(encode_response(r, small).error() == errc::buffer_too_small);
  r.id = static_cast<data_id>(9);
  CHECK(encode_response(r, out).error() == errc::tformat_unknown_data_id);

  response e;
  e.id = data_id::eeprom_read;
  e.address = 5;
  e.busy = true;
  e.edf = 0x77;  // ignored while busy: EDF is 00
  REQUIRE(encode_response(e, out).value() == 4);
  CHECK(std::vector<std::uint8_t>(out, out + 4) == with_crc({0xEA, 0x85, 0x00}));
  e.address = 128;
  CHECK(encode_response(e, out).error() == errc::out_of_range);

  CHECK(status_field(0x04) == sf::ea0);
  CHECK(status_field(0x10) == sf::ea1);
  CHECK(status_field(0x0B) == 0);  // OS, FS, OF are not in ea0/ea1
  CHECK(status_field(0, true, true) == (sf::ca0 | sf::ca1));
}

TEST_CASE("round trip: master request -> encoder model -> master decode, every Data ID") {
  devices::ts5700n8500::emulator enc;
  enc.set_position(0x1ABCD, 0x4321);
  enc.set_condition(almc_bit::ba, true);
  std::uint32_t now = 1000;
  for (const auto& row : table1) {
    CAPTURE(static_cast<int>(row.id));
    std::uint8_t req[4] = {};
    if (row.id == data_id::eeprom_read) {  // a write reads back once the page is specified again
      const std::size_t k = encode_request(data_id::eeprom_write, 127, 0, req).value();
      REQUIRE(enc.respond(byte_view(req, k), now).size > 0U);
      now += 100000;
    }
    const std::size_t n = encode_request(row.id, 3, 0x5A, req).value();
    const devices::ts5700n8500::reply rep = enc.respond(byte_view(req, n), now);
    now += 100000;  // past any busy window
    REQUIRE(rep.size == layout_of(row.id).size);
    const auto r = decode_response_for(byte_view(req, n), rep.view());
    REQUIRE(r.is_complete());
    CHECK(r->id == row.id);
    if (layout_of(row.id).abs()) {
      CHECK(r->abs == 0x1ABCD);
    }
    if (layout_of(row.id).abm()) {
      CHECK(r->abm == 0x4321);
    }
    if (layout_of(row.id).sf()) {
      CHECK(r->ea1());  // battery alarm
    }
    if (row.id == data_id::read_all) {
      CHECK(r->almc == static_cast<std::uint8_t>(almc_bit::ba));
      CHECK(r->enid == 0x11);
    }
    if (row.id == data_id::eeprom_read) {
      CHECK(r->edf == 0x5A);  // written by the ID6 row before it
    }
  }
}

TEST_CASE("decode_response: 17 bits by default, 23 and 11 selectable, ENID-driven for ID3") {
  const auto abs23 = with_crc({0x02, 0x00, 0xFF, 0xFF, 0x7F});  // 0x7FFFFF: 23 bits
  CHECK(decode_response(view(abs23)).error() == errc::out_of_range);
  decode_options o23;
  o23.res = {23, 16};
  CHECK(decode_response(view(abs23), o23).value().abs == 0x7FFFFF);
  decode_options o11;
  o11.res = {11, 16};
  CHECK(decode_response(view(with_crc({0x02, 0x00, 0x00, 0x08, 0x00})), o11).error() ==
        errc::out_of_range);
  CHECK(decode_response(view(with_crc({0x02, 0x00, 0xFF, 0x07, 0x00})), o11).value().abs == 0x7FF);

  const auto id3_23 = with_crc({0x1A, 0x00, 0xFF, 0xFF, 0x7F, 0x17, 0x01, 0x00, 0x00, 0x00});
  CHECK(decode_response(view(id3_23)).error() == errc::out_of_range);
  decode_options by_enid;
  by_enid.resolution_from_enid = true;
  CHECK(decode_response(view(id3_23), by_enid).value().abs == 0x7FFFFF);
}

TEST_CASE("every single-bit flip of every valid request is detected by the encoder side") {
  for (const auto& row : table1) {
    std::uint8_t req[4] = {};
    const std::size_t n = encode_request(row.id, 0x2C, 0x96, req).value();
    for (std::size_t byte = 0; byte < n; ++byte) {
      for (unsigned bit = 0; bit < 8; ++bit) {
        std::uint8_t bad[4] = {req[0], req[1], req[2], req[3]};
        bad[byte] = static_cast<std::uint8_t>(bad[byte] ^ (1U << bit));
        CAPTURE(static_cast<int>(row.id));
        CAPTURE(byte);
        CAPTURE(bit);
        // the parity bit makes every CF flip visible; the CRC every other flip
        CHECK(decode_request(byte_view(bad, n)).is_failed());
      }
    }
  }
}

TEST_CASE("decode_response_for: a short response needs more input") {
  std::uint8_t req[1] = {};
  (void)encode_request(data_id::read_all, req);
  const std::uint8_t part[3] = {0x1A, 0x00, 0x00};
  const auto r = decode_response_for(byte_view(req, 1), byte_view(part, 3));
  CHECK(r.is_incomplete());
  CHECK(r.needed() == 8);
}

TEST_CASE("encode_response: an ABM above 24 bits is out of range, as an ABS is") {
  response r;
  r.id = data_id::read_all;
  r.abs = 0x1FFFF;
  r.abm = 0xFFFFFF;  // 24 bits: fits
  std::uint8_t out[11] = {};
  CHECK(encode_response(r, out).ok());
  r.abm = 1U << 24U;
  CHECK(encode_response(r, out).error() == errc::out_of_range);
  r.id = data_id::read_abm;  // ABM alone
  CHECK(encode_response(r, out).error() == errc::out_of_range);
}

TEST_CASE("encode_request: the form without fields asks EEPROM address 0, with data 0") {
  // encode_request(id, out) is encode_request(id, 0, 0, out): for the EEPROM IDs, a read of
  // address 0 and a write of 0 at address 0.
  std::uint8_t out[4] = {0xAA, 0xAA, 0xAA, 0xAA};
  REQUIRE(encode_request(data_id::eeprom_read, out).value() == 3);
  CHECK(std::vector<std::uint8_t>(out, out + 3) == with_crc({0xEA, 0x00}));
  REQUIRE(encode_request(data_id::eeprom_write, out).value() == 4);
  CHECK(std::vector<std::uint8_t>(out, out + 4) == with_crc({0x32, 0x00, 0x00}));
}

TEST_CASE("decode_response: the fields a response's layout does not carry read 0") {
  // ID3 carries SF, ABS, ENID, ABM and ALMC: no EEPROM address, busy bit or data.
  const auto id3 = with_crc({0x1A, 0x10, 0xFF, 0xFF, 0x01, 0x11, 0xFF, 0xFF, 0x00, 0xD4});
  const auto r3 = decode_response(view(id3));
  REQUIRE(r3.is_complete());
  CHECK(r3->address == 0);
  CHECK_FALSE(r3->busy);
  CHECK(r3->edf == 0);
  // The EEPROM responses carry ADF and EDF: no SF (its bits read 0), ENID, ALMC, ABS or ABM.
  for (const std::uint8_t cf : {std::uint8_t{0xEA}, std::uint8_t{0x32}}) {
    CAPTURE(static_cast<int>(cf));
    const auto e = decode_response(view(with_crc({cf, 0x7F, 0xFF})));
    REQUIRE(e.is_complete());
    CHECK(e->address == 0x7F);
    CHECK_FALSE(e->busy);
    CHECK(e->edf == 0xFF);
    CHECK(e->sf == 0);
    CHECK_FALSE(e->ea0());
    CHECK_FALSE(e->ca1());
    CHECK(e->enid == 0);
    CHECK(e->almc == 0);
    CHECK(e->abs == 0);
    CHECK(e->abm == 0);
  }
}

TEST_CASE("check_response: the request's and the response's field as expected() and received()") {
  std::uint8_t req[4] = {};
  REQUIRE(encode_request(data_id::eeprom_read, 9, 0, req).ok());
  const auto address = decode_response_for(byte_view(req, 3), view(with_crc({0xEA, 0x08, 0x42})));
  CHECK(address.error() == errc::tformat_address_mismatch);
  CHECK(address.expected() == 9);
  CHECK(address.received() == 8);
  CHECK(address.consumed() == 4);

  REQUIRE(encode_request(data_id::eeprom_write, 9, 0x55, req).ok());
  const auto data = decode_response_for(byte_view(req, 4), view(with_crc({0x32, 0x09, 0x54})));
  CHECK(data.error() == errc::tformat_data_mismatch);
  CHECK(data.expected() == 0x55);
  CHECK(data.received() == 0x54);

  // A communication alarm compares no field: no evidence, expected() and received() 0.
  REQUIRE(encode_request(data_id::read_all, req).ok());
  const auto alarm = decode_response_for(byte_view(req, 1),
                                         view(with_crc({0x1A, 0xC0, 0, 0, 0, 0x11, 0, 0, 0, 0})));
  CHECK(alarm.error() == errc::tformat_communication_alarm);
  CHECK(alarm.expected() == 0);
  CHECK(alarm.received() == 0);
  CHECK(alarm.consumed() == 11);
}

TEST_CASE("check_response: a malformed request frame is invalid_argument, consuming nothing") {
  const auto id0 = with_crc({0x02, 0x00, 0x40, 0xE2, 0x01});
  const decode_result<response> r = decode_response(view(id0));
  REQUIRE(r.is_complete());
  const auto none = check_response(byte_view{}, r);
  CHECK(none.error() == errc::invalid_argument);
  CHECK(none.consumed() == 0);
  const std::uint8_t short_read[2] = {0xEA, 0x05};  // IDD without its CRC
  const auto part = check_response(byte_view(short_read, 2), r);
  CHECK(part.error() == errc::invalid_argument);
  CHECK(part.consumed() == 0);
}

TEST_CASE("decode_request: with no byte, the CF is needed, one byte") {
  const auto q = decode_request(byte_view{});
  REQUIRE(q.is_incomplete());
  CHECK(q.needed() == 1);
}

TEST_CASE("decode_request: the fields a request does not carry read 0") {
  for (const auto& row : table1) {
    if (request_size(row.id) != 1U) {
      continue;
    }
    CAPTURE(static_cast<int>(row.id));
    const std::uint8_t cf[1] = {control_field(row.id)};
    const auto q = decode_request(byte_view(cf, 1));
    REQUIRE(q.is_complete());
    CHECK(q->cf == cf[0]);
    CHECK(q->address == 0);  // no ADF
    CHECK(q->edf == 0);      // no EDF
    CHECK(q->crc == 0);      // no CRC
  }
  const auto read = with_crc({0xEA, 0x05});  // IDD: CF ADF CRC, no EDF
  const auto q = decode_request(view(read));
  REQUIRE(q.is_complete());
  CHECK(q->address == 5);
  CHECK(q->edf == 0);
  CHECK(q->crc == read[2]);
}
