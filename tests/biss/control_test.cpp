// BiSS-C control communication: master and slave state machines talking frame by frame, with
// reads, writes, sequential access, wait states, aborts and injected bit errors. The CDM
// sequence is also checked against the slot table of docs/biss.md §3, built here.
#include "motionbus/biss/control.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "../support/bit_strings.hpp"
#include "../support/reference_crc.hpp"

using namespace motionbus;
using namespace motionbus::biss;

namespace {

struct test_registers {
  std::array<std::uint8_t, 128> mem{};
  std::array<bool, 128> read_only{};
  std::array<bool, 128> hidden{};
  int write_delay = 0;  // frames of wait states after each write
  int busy = 0;
  int writes = 0;

  bool readable(std::uint8_t a) const { return !hidden[a]; }
  bool writable(std::uint8_t a) const { return !hidden[a] && !read_only[a]; }
  bool ready() const { return busy == 0; }
  std::uint8_t read(std::uint8_t a) { return mem[a]; }
  void write(std::uint8_t a, std::uint8_t v) {
    mem[a] = v;
    busy = write_delay;
    ++writes;
  }
  void tick() {
    if (busy > 0) {
      --busy;
    }
  }
};

// Frame loop: master CDM -> slave, slave CDS -> master (next frame). `cdm_fault` and
// `cds_fault` may flip a bit in a given frame. Returns the frames run.
struct frame_link {
  frame_link(control_master& master, control_slave<test_registers>& slave, test_registers& regs)
      : m(master), s(slave), r(regs) {}
  control_master& m;
  control_slave<test_registers>& s;
  test_registers& r;
  std::function<bool(std::size_t, bool)> cdm_fault = [](std::size_t, bool b) { return b; };
  std::function<bool(std::size_t, bool)> cds_fault = [](std::size_t, bool b) { return b; };
  std::vector<int> cdm_log;

  std::size_t run(std::size_t limit = 100000) {
    bool cds = false;
    std::size_t k = 0;
    for (; k < limit && m.busy(); ++k) {
      const bool cdm = cdm_fault(k, m.step(cds));
      cdm_log.push_back(cdm ? 1 : 0);
      cds = cds_fault(k, s.step(cdm));
      r.tick();
    }
    return k;
  }
  void idle(std::size_t frames) {
    bool cds = false;
    for (std::size_t k = 0; k < frames; ++k) {
      cds = s.step(m.step(cds));
      r.tick();
    }
  }
};

std::string bits(std::uint32_t v, unsigned n) {
  return testutil::bits_of(v, n);
}

std::uint32_t ref_crc4(std::uint32_t v, unsigned n) {
  return ref::crc_of_bits({4, 0x3, 0, false, false, 0xF},
                          testutil::as_ints(testutil::bits_of(v, n)));
}

}  // namespace

TEST_CASE("control CRC4s match long division") {
  for (unsigned id = 0; id < 8; ++id) {
    for (unsigned a = 0; a < 128; ++a) {
      CHECK(header_crc(static_cast<std::uint8_t>(id), static_cast<std::uint8_t>(a)) ==
            ref_crc4((1U << 10U) | (id << 7U) | a, 11));
    }
  }
  for (unsigned d = 0; d < 256; ++d) {
    CHECK(data_crc(static_cast<std::uint8_t>(d)) == ref_crc4(d, 8));
  }
}

TEST_CASE("read: the CDM sequence follows the slot table, the byte arrives with its CRC") {
  test_registers regs;
  regs.mem[0x42] = 0x63;
  control_master m;
  control_slave<test_registers> s(regs, {5});
  std::uint8_t out[1] = {};
  REQUIRE(m.start_read(5, 0x42, mutable_byte_view(out, 1)) == errc::ok);
  frame_link l{m, s, regs};
  const std::size_t frames = l.run();
  CHECK(m.state() == control_state::done);
  CHECK(m.error() == errc::ok);
  CHECK(out[0] == 0x63);
  CHECK(frames == control_master::frames_for(1) - preamble_frames);  // the master was silent
  // The slots: S CTS ID ADR ~CRC4 R W | S 8 zeros 4 zeros P
  std::string sent;
  for (int b : l.cdm_log) {
    sent.push_back(b != 0 ? '1' : '0');
  }
  const std::string want =
      "1"
      "1" +
      bits(5, 3) + bits(0x42, 7) + bits(ref_crc4((1U << 10U) | (5U << 7U) | 0x42U, 11), 4) + "10" +
      "1" + std::string(12, '0') + "0";
  CHECK(sent.substr(0, want.size()) == want);
}

TEST_CASE("write: the data and its CRC go out, the echo confirms, the register changes") {
  test_registers regs;
  control_master m;
  control_slave<test_registers> s(regs);
  const std::uint8_t data[1] = {0xA7};
  REQUIRE(m.start_write(0, 0x4C, byte_view(data, 1)) == errc::ok);
  frame_link l{m, s, regs};
  l.run();
  CHECK(m.state() == control_state::done);
  CHECK(regs.mem[0x4C] == 0xA7);
  std::string sent;
  for (int b : l.cdm_log) {
    sent.push_back(b != 0 ? '1' : '0');
  }
  const std::string want = "11" + bits(0, 3) + bits(0x4C, 7) +
                           bits(ref_crc4((1U << 10U) | 0x4CU, 11), 4) + "01" + "1" + bits(0xA7, 8) +
                           bits(ref_crc4(0xA7, 8), 4) + "0";
  CHECK(sent.substr(0, want.size()) == want);
}

TEST_CASE("sequential reads and writes, with wait states after each write") {
  test_registers regs;
  for (unsigned a = 0; a < 128; ++a) {
    regs.mem[a] = static_cast<std::uint8_t>(a * 3U);
  }
  regs.write_delay = 25;
  control_master m;
  control_slave<test_registers> s(regs, {2});
  std::uint8_t out[8] = {};
  REQUIRE(m.start_read(2, 0x10, mutable_byte_view(out, 8)) == errc::ok);
  frame_link l{m, s, regs};
  l.run();
  REQUIRE(m.state() == control_state::done);
  for (unsigned i = 0; i < 8; ++i) {
    CHECK(out[i] == static_cast<std::uint8_t>((0x10 + i) * 3U));
  }
  const std::uint8_t data[4] = {1, 2, 3, 4};
  REQUIRE(m.start_write(2, 0x7C, byte_view(data, 4)) == errc::ok);
  const std::size_t frames = l.run();
  REQUIRE(m.state() == control_state::done);
  CHECK(m.transferred() == 4);
  CHECK(regs.mem[0x7C] == 1);
  CHECK(regs.mem[0x7F] == 4);
  CHECK(regs.writes == 4);
  // three writes' wait states delayed the following starts
  CHECK(frames >= 18U + 4U * 14U + 3U * 20U);
  // reading back right after the last write waits for it too
  std::uint8_t back[4] = {};
  REQUIRE(m.start_read(2, 0x7C, mutable_byte_view(back, 4)) == errc::ok);
  l.run();
  CHECK(m.state() == control_state::done);
  CHECK(back[3] == 4);
}

TEST_CASE("refused, unanswered and out-of-range accesses") {
  test_registers regs;
  regs.read_only[0x42] = true;
  regs.hidden[0x50] = true;
  control_master m;
  control_slave<test_registers> s(regs, {1});
  frame_link l{m, s, regs};
  const std::uint8_t data[1] = {9};
  REQUIRE(m.start_write(1, 0x42, byte_view(data, 1)) == errc::ok);
  l.run();
  CHECK(m.error() == errc::biss_access_denied);
  CHECK(regs.writes == 0);
  std::uint8_t out[2] = {};
  REQUIRE(m.start_read(1, 0x50, mutable_byte_view(out, 1)) == errc::ok);
  l.run();
  CHECK(m.error() == errc::biss_access_denied);
  REQUIRE(m.start_read(3, 0x10, mutable_byte_view(out, 1)) == errc::ok);  // nobody has ID 3
  l.run();
  CHECK(m.error() == errc::biss_not_acknowledged);
  // the slave still works afterwards
  regs.mem[0x10] = 0x5A;
  REQUIRE(m.start_read(1, 0x10, mutable_byte_view(out, 1)) == errc::ok);
  l.run();
  CHECK(m.state() == control_state::done);
  CHECK(out[0] == 0x5A);
  // arguments
  CHECK(m.start_read(8, 0, mutable_byte_view(out, 1)) == errc::invalid_argument);
  CHECK(m.start_read(0, 0x80, mutable_byte_view(out, 1)) == errc::invalid_argument);
  CHECK(m.start_read(0, 0x7F, mutable_byte_view(out, 2)) == errc::invalid_argument);
  CHECK(m.start_read(0, 0, mutable_byte_view{}) == errc::invalid_argument);
  REQUIRE(m.start_read(1, 0, mutable_byte_view(out, 1)) == errc::ok);
  CHECK(m.start_read(1, 0, mutable_byte_view(out, 1)) == errc::biss_busy);
}

TEST_CASE("wait states beyond the bound time out; abort sends the slave back to idle") {
  test_registers regs;
  regs.busy = 1000000;  // a slave that never gets ready
  control_options opt;
  opt.max_wait_frames = 50;
  control_master m(opt);
  control_slave<test_registers> s(regs);
  frame_link l{m, s, regs};
  std::uint8_t out[1] = {};
  REQUIRE(m.start_read(0, 0x01, mutable_byte_view(out, 1)) == errc::ok);
  const std::size_t frames = l.run();
  CHECK(m.error() == errc::biss_timeout);
  CHECK(frames <= 18U + 1U + 51U + 1U);
  regs.busy = 0;
  regs.mem[1] = 0x11;
  REQUIRE(m.start_read(0, 0x01, mutable_byte_view(out, 1)) == errc::ok);
  l.run();
  CHECK(m.state() == control_state::done);
  CHECK(out[0] == 0x11);

  // abort in the middle of a header
  REQUIRE(m.start_read(0, 0x01, mutable_byte_view(out, 1)) == errc::ok);
  bool cds = false;
  for (int k = 0; k < 8; ++k) {
    cds = s.step(m.step(cds));
  }
  m.abort();
  CHECK(m.error() == errc::biss_aborted);
  const bool after_abort = m.step(cds);
  CHECK(!after_abort);
  cds = s.step(after_abort);
  // the next access needs the 14 zeros first, then works
  out[0] = 0;
  REQUIRE(m.start_read(0, 0x01, mutable_byte_view(out, 1)) == errc::ok);
  const std::size_t after = l.run();
  CHECK(m.error() == errc::ok);
  CHECK(m.state() == control_state::done);
  CHECK(out[0] == 0x11);
  CHECK(after >= preamble_frames);
}

TEST_CASE("injected bit errors: header CRC, read data, write data, echoes") {
  test_registers regs;
  regs.mem[0x20] = 0xC3;
  control_master m;
  control_slave<test_registers> s(regs);
  std::uint8_t out[1] = {};
  // every single CDM bit flip within the header (after S) makes the access fail cleanly
  for (std::size_t slot = 1; slot < 18; ++slot) {
    frame_link l{m, s, regs};
    l.cdm_fault = [slot](std::size_t k, bool b) { return k == slot ? !b : b; };
    REQUIRE(m.start_read(0, 0x20, mutable_byte_view(out, 1)) == errc::ok);
    l.run();
    CAPTURE(slot);
    CHECK(m.state() == control_state::failed);
    frame_link quiet{m, s, regs};
    quiet.idle(preamble_frames);
  }
  // a flipped CDS bit in the read data or its CRC is a CRC mismatch
  for (std::size_t k = 19; k < 19 + 12; ++k) {
    frame_link l{m, s, regs};
    l.cds_fault = [k](std::size_t f, bool b) { return f == k ? !b : b; };
    REQUIRE(m.start_read(0, 0x20, mutable_byte_view(out, 1)) == errc::ok);
    l.run();
    CAPTURE(k);
    CHECK(m.error() == errc::crc_mismatch);
    frame_link quiet{m, s, regs};
    quiet.idle(preamble_frames);
  }
  // a flipped CDM bit in the write data or CRC: the slave refuses, the master is told
  const std::uint8_t data[1] = {0x3C};
  for (std::size_t k = 19; k < 19 + 12; ++k) {
    frame_link l{m, s, regs};
    l.cdm_fault = [k](std::size_t f, bool b) { return f == k ? !b : b; };
    REQUIRE(m.start_write(0, 0x21, byte_view(data, 1)) == errc::ok);
    l.run();
    CAPTURE(k);
    CHECK(m.error() == errc::biss_write_not_confirmed);
    CHECK(regs.mem[0x21] == 0);
    frame_link quiet{m, s, regs};
    quiet.idle(preamble_frames);
  }
  CHECK(s.rejected_writes() == 12);
  // a flipped echo (CDS) of the R/W bits
  frame_link l{m, s, regs};
  l.cds_fault = [](std::size_t f, bool b) { return f == 17 ? !b : b; };
  REQUIRE(m.start_read(0, 0x20, mutable_byte_view(out, 1)) == errc::ok);
  l.run();
  CHECK(m.error() == errc::biss_access_denied);  // 10 became 11
}

TEST_CASE("sequential read past a hidden register: the slave stops answering, the master fails") {
  test_registers regs;
  regs.mem[0x10] = 0x11;
  regs.hidden[0x11] = true;  // the next address may not be read
  control_master m;
  control_slave<test_registers> s(regs, {0});
  std::uint8_t out[2] = {};
  REQUIRE(m.start_read(0, 0x10, mutable_byte_view(out, 2)) == errc::ok);
  frame_link l{m, s, regs};
  l.run();
  CHECK(m.state() == control_state::failed);
  CHECK(m.error() != errc::ok);
  CHECK(out[0] == 0x11);  // the first byte arrived
  CHECK(s.accesses() == 1);
}

TEST_CASE("after a complete access the master's 0 ends it at the slave") {
  test_registers regs;
  regs.mem[0x20] = 0x5A;
  control_master m;
  control_slave<test_registers> s(regs, {0});
  std::uint8_t out[1] = {};
  REQUIRE(m.start_read(0, 0x20, mutable_byte_view(out, 1)) == errc::ok);
  frame_link l{m, s, regs};
  l.run();
  REQUIRE(m.state() == control_state::done);
  CHECK(!s.step(false));  // the frame after P carries 0: the slave ends the access
  l.idle(preamble_frames);
  // a new access after the preamble still works
  REQUIRE(m.start_read(0, 0x20, mutable_byte_view(out, 1)) == errc::ok);
  out[0] = 0;
  l.run();
  CHECK(m.state() == control_state::done);
  CHECK(out[0] == 0x5A);
}

namespace {

// The master and slave talking, an observer tapping each frame's CDS and the CDM sent after it;
// the events it reports (kind none left out). `cds_fault` flips the CDS of a given frame.
std::vector<observed_access> observe(
    control_master& m, control_slave<test_registers>& s, test_registers& regs,
    std::size_t extra_frames,
    const std::function<bool(std::size_t, bool)>& cds_fault = [](std::size_t, bool b) {
      return b;
    }) {
  control_observer obs;
  std::vector<observed_access> seen;
  bool cds = false;
  std::size_t tail = 0;
  for (std::size_t k = 0; k < 100000 && tail < extra_frames; ++k) {
    tail += m.busy() ? 0U : 1U;
    const bool cdm = m.step(cds);
    const observed_access e = obs.step(cds, cdm);
    if (e.kind != observed_kind::none) {
      seen.push_back(e);
    }
    cds = cds_fault(k, s.step(cdm));
    regs.tick();
  }
  return seen;
}

}  // namespace

TEST_CASE("observer: a read, its header and byte with the slave's CRC4") {
  test_registers regs;
  regs.mem[0x42] = 0x63;
  control_master m;
  control_slave<test_registers> s(regs, {5});
  std::uint8_t out[1] = {};
  REQUIRE(m.start_read(5, 0x42, mutable_byte_view(out, 1)) == errc::ok);
  const auto seen = observe(m, s, regs, 3);
  REQUIRE(seen.size() == 2);
  CHECK(seen[0].kind == observed_kind::header);
  CHECK(seen[0].slave_id == 5);
  CHECK(seen[0].address == 0x42);
  CHECK(seen[0].cts);
  CHECK_FALSE(seen[0].write);
  CHECK(seen[0].crc == header_crc(5, 0x42));
  CHECK(seen[0].crc_ok);
  CHECK(seen[0].echo == 0x2);
  CHECK(seen[1].kind == observed_kind::byte);
  CHECK(seen[1].address == 0x42);
  CHECK(seen[1].data == 0x63);
  CHECK(seen[1].crc == data_crc(0x63));
  CHECK(seen[1].crc_ok);
  CHECK_FALSE(seen[1].stop);
  CHECK(seen[1].waits == 0);
}

TEST_CASE("observer: a sequential write with wait states, the echo and P per byte") {
  test_registers regs;
  regs.write_delay = 3;
  control_master m;
  control_slave<test_registers> s(regs, {2});
  const std::uint8_t data[2] = {0xA5, 0x3C};
  REQUIRE(m.start_write(2, 0x10, byte_view(data, 2)) == errc::ok);
  const auto seen = observe(m, s, regs, 3);
  CHECK(m.state() == control_state::done);
  REQUIRE(seen.size() == 3);
  CHECK(seen[0].write);
  CHECK(seen[0].echo == 0x1);
  for (std::size_t i = 0; i < 2; ++i) {
    CAPTURE(i);
    CHECK(seen[i + 1].kind == observed_kind::byte);
    CHECK(seen[i + 1].write);
    CHECK(seen[i + 1].address == 0x10 + i);
    CHECK(seen[i + 1].data == data[i]);
    CHECK(seen[i + 1].answer == data[i]);
    CHECK(seen[i + 1].answer_crc == data_crc(data[i]));
    CHECK(seen[i + 1].crc_ok);
    CHECK_FALSE(seen[i + 1].stop);
  }
  CHECK(seen[1].waits == 0);
  // the first write keeps the slave busy 3 frames from its last CRC4 slot: that slot and P
  // pass before the next S, one wait state is left
  CHECK(seen[2].waits == 1);
}

TEST_CASE("observer: a corrupted read byte is CRC-bad; a refused header ends the access") {
  test_registers regs;
  regs.mem[0x20] = 0xC3;
  regs.hidden[0x30] = true;
  control_master m;
  control_slave<test_registers> s(regs, {0});
  std::uint8_t out[1] = {};
  REQUIRE(m.start_read(0, 0x20, mutable_byte_view(out, 1)) == errc::ok);
  // frame 20 carries the answer to slot 19 (D7 after S at 18)
  auto seen = observe(m, s, regs, 3, [](std::size_t f, bool b) { return f == 19 ? !b : b; });
  REQUIRE(seen.size() == 2);
  CHECK(seen[1].data == (0xC3 ^ 0x80));
  CHECK(seen[1].crc == data_crc(0xC3));
  CHECK_FALSE(seen[1].crc_ok);
  CHECK(m.error() == errc::crc_mismatch);

  REQUIRE(m.start_read(0, 0x30, mutable_byte_view(out, 1)) == errc::ok);
  seen = observe(m, s, regs, preamble_frames + 3);
  REQUIRE(seen.size() == 1);  // no byte after "11"
  CHECK(seen[0].echo == 0x3);
  CHECK(seen[0].address == 0x30);

  REQUIRE(m.start_read(3, 0x20, mutable_byte_view(out, 1)) == errc::ok);  // nobody is ID 3
  seen = observe(m, s, regs, preamble_frames + 3);
  REQUIRE(seen.size() == 1);
  CHECK(seen[0].echo == 0x0);
  CHECK(seen[0].slave_id == 3);
}

TEST_CASE("observer: a bad header CRC4 is reported; reset() forgets a half-seen access") {
  control_observer obs;
  // preamble seen (a fresh observer counts as after one), then a header with its CRC flipped
  const std::uint32_t h = header_bits(1, 0x05, false) ^ (1U << 2U);
  observed_access last{};
  for (unsigned i = 0; i < 18; ++i) {
    const observed_access e = obs.step(i >= 17U, ((h >> (17U - i)) & 1U) != 0U);  // echo "10"
    if (e.kind != observed_kind::none) {
      last = e;
    }
  }
  CHECK(last.kind == observed_kind::none);  // W's answer not yet seen
  last = obs.step(false, false);
  CHECK(last.kind == observed_kind::header);
  CHECK_FALSE(last.crc_ok);
  CHECK(last.crc == (header_crc(1, 0x05) ^ 0x1U));
  obs.reset();
  for (unsigned i = 0; i < 18; ++i) {
    CHECK(obs.step(false, ((h >> (17U - i)) & 1U) != 0U).kind == observed_kind::none);
  }
}

namespace {

// Slots sent (CDM) and the slave's answer to each (CDS, one frame later), through an observer.
std::vector<observed_access> feed_slots(control_observer& obs, const std::string& cdm,
                                        const std::string& cds) {
  std::vector<observed_access> seen;
  for (std::size_t i = 0; i <= cdm.size(); ++i) {
    const bool answer = i > 0 && cds[i - 1] == '1';
    const bool slot = i < cdm.size() && cdm[i] == '1';
    const observed_access e = obs.step(answer, slot);
    if (e.kind != observed_kind::none) {
      seen.push_back(e);
    }
  }
  return seen;
}

std::string header_slots(std::uint8_t id, std::uint8_t address, const char* rw) {
  return bits(header_bits(id, address, false) >> 2U, 16) + rw;  // S, CTS, ID, ADR, CRC4, R, W
}

}  // namespace

TEST_CASE("observer: an invalid R/W pair, a master ending in a wait state, P sent as 1") {
  const std::string quiet(preamble_frames, '0');
  control_observer obs;
  // R = W = 1 from the master: reported, and the access ends (the slave's 1s are no data)
  std::string cdm = header_slots(2, 0x11, "11") + std::string(13, '1');
  std::string cds = std::string(16, '0') + "11" + std::string(13, '1');
  auto seen = feed_slots(obs, cdm, cds);
  REQUIRE(seen.size() == 1);
  CHECK(seen[0].echo == 0x3);
  CHECK(seen[0].address == 0x11);
  CHECK(seen[0].slave_id == 2);
  CHECK(seen[0].crc_ok);
  CHECK_FALSE(seen[0].write);
  // a read, the slave busy in the S slot, then the master gives up (CDM 0): nothing more
  cdm = quiet + header_slots(2, 0x11, "10") + "1" + "0" + std::string(12, '1') + "0";
  cds = quiet + std::string(16, '0') + "10" + "0" + std::string(14, '1');
  seen = feed_slots(obs, cdm, cds);
  REQUIRE(seen.size() == 1);
  CHECK(seen[0].kind == observed_kind::header);
  CHECK(seen[0].echo == 0x2);
  // a read byte whose P slot the master sends as 1: the byte is reported, the access ends
  const std::string byte_bits = bits(0xA7, 8) + bits(data_crc(0xA7), 4);
  cdm = quiet + header_slots(2, 0x12, "10") + "1" + std::string(12, '0') + "1" + "1" +
        std::string(12, '0') + "0";
  cds = quiet + std::string(16, '0') + "10" + "1" + byte_bits + "0" + "1" + byte_bits + "0";
  seen = feed_slots(obs, cdm, cds);
  REQUIRE(seen.size() == 2);
  CHECK(seen[1].kind == observed_kind::byte);
  CHECK(seen[1].address == 0x12);
  CHECK(seen[1].data == 0xA7);
  CHECK(seen[1].crc_ok);
}

TEST_CASE("abort() with no access running changes nothing") {
  control_master m;
  m.abort();
  CHECK(m.state() == control_state::idle);
  CHECK(m.error() == errc::ok);
}

TEST_CASE(
    "write echo with a bad CRC, a 1 in the P slot, sequential access past 0x7F and into a "
    "read-only register") {
  test_registers regs;
  control_master m;
  control_slave<test_registers> s(regs);
  // the slave echoes the written value right but a CRC bit flipped (CDS, frames 27..30): the
  // master does not take the write as confirmed, though the slave, which got it right, wrote it
  const std::uint8_t data[1] = {0x3C};
  for (std::size_t k = 27; k < 31; ++k) {
    frame_link l{m, s, regs};
    l.cds_fault = [k](std::size_t f, bool b) { return f == k ? !b : b; };
    REQUIRE(m.start_write(0, 0x21, byte_view(data, 1)) == errc::ok);
    l.run();
    CAPTURE(k);
    CHECK(m.error() == errc::biss_write_not_confirmed);
    CHECK(regs.mem[0x21] == 0x3C);
    regs.mem[0x21] = 0;
    frame_link quiet{m, s, regs};
    quiet.idle(preamble_frames);
  }
  // a 1 from the master in the P slot (frame 31) of a read: the slave takes it as no P and
  // ignores the rest of the access. Shown by a 1 in the frame after P: after a normal P the S
  // of the next address (0x21, readable and ready: the slave answers its S with 1), after the
  // 1 in P nothing (0)
  regs.mem[0x20] = 0x5A;
  std::uint8_t out[2] = {};
  for (const bool flip : {false, true}) {
    frame_link l{m, s, regs};
    l.cdm_fault = [flip](std::size_t f, bool b) { return flip && f == 31 ? !b : b; };
    REQUIRE(m.start_read(0, 0x20, mutable_byte_view(out, 1)) == errc::ok);
    REQUIRE(l.run(32) == 32);  // up to P
    CAPTURE(flip);
    CHECK(l.cdm_log[18] == 1);  // the byte's S
    CHECK(l.cdm_log[31] == (flip ? 1 : 0));
    CHECK(s.step(true) == !flip);  // frame 32, in the master's place
    m.abort();
    frame_link quiet{m, s, regs};
    quiet.idle(preamble_frames);
  }
  // a read of the last register (0x7F) up to P, then an S for the next address: no register
  // past 0x7F, the slave ignores it (answers 0) and reads nothing
  regs.mem[0x7F] = 0x99;
  {
    frame_link l{m, s, regs};
    REQUIRE(m.start_read(0, 0x7F, mutable_byte_view(out, 1)) == errc::ok);
    REQUIRE(l.run(32) == 32);
    CHECK(!s.step(true));  // frame 32, in the master's place
    CHECK(!s.step(true));
    m.abort();
    l.idle(preamble_frames);
  }
  // a sequential write of two bytes whose second register is read-only: the first is written,
  // the slave stops at the second, the master fails
  regs.read_only[0x31] = true;
  const std::uint8_t two[2] = {0x12, 0x34};
  {
    frame_link l{m, s, regs};
    REQUIRE(m.start_write(0, 0x30, byte_view(two, 2)) == errc::ok);
    l.run();
    CHECK(m.state() == control_state::failed);
    CHECK(regs.mem[0x30] == 0x12);
    CHECK(regs.mem[0x31] == 0);
  }
}

TEST_CASE(
    "the master waits max_wait_frames wait states (4096 by default) and times out at the next") {
  // Frames of a read whose slave never gets ready: 18 header slots (frames 0..17), the byte's
  // S in frame 18, then each frame takes one more 0 answer to S (frame 18 + w holds the w-th
  // wait state); the one past the bound fails the access in frame 19 + bound, the last frame
  // run: 20 + bound frames.
  for (const std::size_t bound : {std::size_t{0}, std::size_t{3}, std::size_t{4096}}) {
    for (const bool defaulted : {false, true}) {
      if (defaulted && bound != 4096U) {
        continue;
      }
      CAPTURE(bound);
      CAPTURE(defaulted);
      test_registers regs;
      regs.busy = 1000000;
      control_options opt;
      opt.max_wait_frames = bound;
      control_master m = defaulted ? control_master{} : control_master{opt};
      control_slave<test_registers> s(regs);
      frame_link l{m, s, regs};
      std::uint8_t out[1] = {};
      REQUIRE(m.start_read(0, 0x01, mutable_byte_view(out, 1)) == errc::ok);
      CHECK(l.run() == 20U + bound);
      CHECK(m.error() == errc::biss_timeout);
      CHECK(m.frames() == 20U + bound);
    }
  }
  CHECK(control_options{}.max_wait_frames == 4096U);
}

namespace {

// Registers that answer each S slot with `w` wait states (ready() false w times, then true),
// for every byte alike.
struct paced_registers {
  std::array<std::uint8_t, 128> mem{};
  int w = 0;
  int pending = 0;
  bool readable(std::uint8_t) const { return true; }
  bool writable(std::uint8_t) const { return true; }
  bool ready() {
    if (pending > 0) {
      --pending;
      return false;
    }
    pending = w;
    return true;
  }
  std::uint8_t read(std::uint8_t a) { return mem[a]; }
  void write(std::uint8_t a, std::uint8_t v) { mem[a] = v; }
};

}  // namespace

TEST_CASE("the wait-state bound holds per byte: each byte of a sequential access may use it all") {
  // control_options: max_wait_frames is counted for each byte. Four bytes each waited for
  // `w` frames complete with a bound of w (4w wait states in all); a bound of w - 1 fails the
  // first byte.
  for (const int w : {1, 3}) {
    for (const bool write : {false, true}) {
      for (const int bound : {w, w - 1}) {
        CAPTURE(w);
        CAPTURE(write);
        CAPTURE(bound);
        paced_registers regs;
        regs.w = w;
        regs.pending = w;
        for (unsigned a = 0; a < 128; ++a) {
          regs.mem[a] = static_cast<std::uint8_t>(0xA0U + a);
        }
        control_options opt;
        opt.max_wait_frames = static_cast<std::size_t>(bound);
        control_master m(opt);
        control_slave<paced_registers> s(regs);
        std::uint8_t out[4] = {};
        const std::uint8_t data[4] = {0x11, 0x22, 0x33, 0x44};
        REQUIRE((write ? m.start_write(0, 0x20, byte_view(data, 4))
                       : m.start_read(0, 0x20, mutable_byte_view(out, 4))) == errc::ok);
        bool cds = false;
        for (int k = 0; k < 1000 && m.busy(); ++k) {
          cds = s.step(m.step(cds));
        }
        if (bound == w) {
          REQUIRE(m.state() == control_state::done);
          CHECK(m.transferred() == 4U);
          for (unsigned i = 0; i < 4U; ++i) {
            CHECK((write ? regs.mem[0x20 + i] : out[i]) ==
                  (write ? data[i] : static_cast<std::uint8_t>(0xC0U + i)));
          }
        } else {
          CHECK(m.error() == errc::biss_timeout);
          CHECK(m.transferred() == 0U);
        }
      }
    }
  }
}

namespace {
control_master fresh_static_master;  // a `static` master, as firmware keeps one
}  // namespace

TEST_CASE(
    "a fresh master: idle, nothing transferred, CDM 0, and all zeros (so a static is in .bss)") {
  // control.hpp's firmware contract: a default-constructed `static` master is all zeros.
  const auto* bytes = reinterpret_cast<const unsigned char*>(&fresh_static_master);
  std::size_t nonzero = 0;
  for (std::size_t i = 0; i < sizeof(control_master); ++i) {
    nonzero += bytes[i] != 0U ? 1U : 0U;
  }
  CHECK(nonzero == 0U);
  control_master m;
  CHECK(m.state() == control_state::idle);
  CHECK(!m.busy());
  CHECK(m.error() == errc::ok);
  CHECK(m.transferred() == 0U);
  CHECK(m.frames() == 0U);
  CHECK(!m.step(true));  // no access: CDM 0
  CHECK(m.frames() == 0U);
}

TEST_CASE("the slave's CDS answer to every slot of a read and a write (docs/biss.md §3's table)") {
  // The CDM slots built here from the table, fed to the slave alone; its answers compared
  // slot by slot: 0 for the preamble and S..CRC4, R and W echoed, 1 for a ready S, the data
  // (read) or its echo (write), ~CRC4 of it, 0 in P; then the 0 that ends the access and two
  // stray 1s, all answered 0 (after a write's data no preamble comes between; after a read's
  // twelve zero slots, P and that 0 make one, and the 1s begin a header).
  for (const bool write : {false, true}) {
    CAPTURE(write);
    test_registers regs;
    regs.mem[0x2A] = 0xB6;
    control_slave<test_registers> s(regs, {3});
    const std::uint8_t address = write ? 0x2B : 0x2A;
    const std::uint8_t byte = write ? 0x5C : 0xB6;
    const std::string header = "1" + bits(3, 3) + bits(address, 7) +
                               bits(ref_crc4((1U << 10U) | (3U << 7U) | address, 11), 4);
    const std::string data =
        write ? bits(byte, 8) + bits(ref_crc4(byte, 8), 4) : std::string(12, '0');
    const std::string cdm = std::string(preamble_frames, '0') + "1" + header +
                            (write ? "01" : "10") + "1" + data + "0" + "011";
    const std::string want = std::string(preamble_frames, '0') + std::string(16, '0') +
                             (write ? "01" : "10") + "1" + bits(byte, 8) +
                             bits(ref_crc4(byte, 8), 4) + "0" + "000";
    REQUIRE(cdm.size() == want.size());
    std::string got;
    for (const char c : cdm) {
      got.push_back(s.step(c == '1') ? '1' : '0');
    }
    CHECK(got == want);
    CHECK(regs.mem[0x2B] == (write ? 0x5C : 0x00));
    CHECK(s.accesses() == 1U);
  }
}

TEST_CASE("the slave serves nothing after an invalid R/W pair or a 0 in the S slot") {
  // After a header whose R and W are both 0 or both 1, or a valid header whose S slot the
  // master sends as 0 (it ended the access), the slave takes no part in the access: the S,
  // data, CRC4 and P slots that follow (no preamble between) are all answered 0, and no
  // register is read or written.
  struct invalid_case {
    const char* rw;
    const char* s;
  };
  const invalid_case cases[] = {{"00", "1"}, {"11", "1"}, {"10", "0"}, {"01", "0"}};
  for (const invalid_case& c : cases) {
    CAPTURE(c.rw);
    CAPTURE(c.s);
    test_registers regs;
    regs.mem[0x2A] = 0xB6;
    control_slave<test_registers> s(regs, {3});
    const std::string header = "11" + bits(3, 3) + bits(0x2A, 7) +
                               bits(ref_crc4((1U << 10U) | (3U << 7U) | 0x2AU, 11), 4) + c.rw;
    const std::string after = std::string(c.s) + "1" + bits(0x5C, 8) + bits(ref_crc4(0x5C, 8), 4) +
                              "0" + "1" + std::string(12, '1') + "0";
    for (std::size_t k = 0; k < preamble_frames; ++k) {
      REQUIRE(!s.step(false));
    }
    for (const char b : header) {
      (void)s.step(b == '1');
    }
    std::string got;
    for (const char b : after) {
      got.push_back(s.step(b == '1') ? '1' : '0');
    }
    CHECK(got == std::string(after.size(), '0'));
    CHECK(regs.mem[0x2A] == 0xB6);
    CHECK(regs.writes == 0);
    CHECK(s.accesses() == 0U);
  }
}

namespace {

// test_registers whose register 0x41 is hidden at the first question and readable after it
// (as a register that a slave makes readable once loaded).
struct late_registers : test_registers {
  int asked = 0;
  bool readable(std::uint8_t a) {
    if (a == 0x41U) {
      return asked++ > 0;
    }
    return !hidden[a];
  }
};

}  // namespace

TEST_CASE("a sequential access refused at a register stays refused if the register opens later") {
  // Once the slave has found the next address not readable it ignores the rest of the access
  // (control.hpp: it stops answering); the master's repeated S gets 0 and times out.
  late_registers regs;
  regs.mem[0x40] = 0x40;
  regs.mem[0x41] = 0x41;
  control_options opt;
  opt.max_wait_frames = 8;
  control_master m(opt);
  control_slave<late_registers> s(regs, {0});
  std::uint8_t out[2] = {};
  REQUIRE(m.start_read(0, 0x40, mutable_byte_view(out, 2)) == errc::ok);
  bool cds = false;
  for (int k = 0; k < 200 && m.busy(); ++k) {
    cds = s.step(m.step(cds));
  }
  CHECK(m.error() == errc::biss_timeout);
  CHECK(out[0] == 0x40);
  CHECK(out[1] == 0x00);
  CHECK(regs.asked >= 1);
  CHECK(s.accesses() == 1U);
}

namespace {

// Feeds an observer the CDM slots `cdm` and the CDS answers `cds` (cds[k] answers cdm[k], so
// it arrives with the next frame), then one more frame; returns every step's result.
std::vector<observed_access> feed_observer(const std::string& cdm, const std::string& cds) {
  control_observer obs;
  std::vector<observed_access> all;
  for (std::size_t k = 0; k <= cdm.size(); ++k) {
    const bool answer = k > 0U && cds[k - 1U] == '1';
    all.push_back(obs.step(answer, k < cdm.size() && cdm[k] == '1'));
  }
  return all;
}

bool all_zero(const observed_access& e) {
  return e.kind == observed_kind::none && e.slave_id == 0U && e.address == 0U && !e.write &&
         !e.cts && e.crc == 0U && !e.crc_ok && e.echo == 0U && e.data == 0U && e.answer == 0U &&
         e.answer_crc == 0U && !e.stop && e.waits == 0U;
}

}  // namespace

TEST_CASE(
    "observer: a read and a write reported as two events each, without the other kind's fields") {
  // Register 0x2A of slave 3 read (0xB6) and written (0x5C), slots as docs/biss.md §3's table
  // gives them. The observer's events are printed whole (the Python binding's repr shows every
  // field), so a field an event's kind does not describe is 0 (false), and a step that
  // completes nothing returns an event with every field 0. After P and the 0 that ends the
  // access, a 1 answered 1 and more slots without a preamble are not a next byte (control.hpp:
  // the access is over; after a write's data the 0s are fewer than a preamble).
  const std::uint32_t hcrc = ref_crc4((1U << 10U) | (3U << 7U) | 0x2AU, 11);
  for (const bool write : {false, true}) {
    CAPTURE(write);
    const std::uint8_t v = write ? 0x5C : 0xB6;
    const std::string slots = bits(v, 8) + bits(ref_crc4(v, 8), 4);
    const std::string cdm = std::string(preamble_frames, '0') + "11" + bits(3, 3) + bits(0x2A, 7) +
                            bits(hcrc, 4) + (write ? "01" : "10") + "1" +
                            (write ? slots : std::string(12, '0')) + "0" + "0" + "1" +
                            std::string(12, '0') + "0" + "000";
    const std::string cds = std::string(preamble_frames, '0') + std::string(16, '0') +
                            (write ? "01" : "10") + "1" + slots + "0" + "0" + "1" +
                            std::string(12, '1') + "0" + "000";
    REQUIRE(cdm.size() == cds.size());
    const std::vector<observed_access> all = feed_observer(cdm, cds);
    std::vector<observed_access> events;
    for (const observed_access& e : all) {
      if (e.kind == observed_kind::none) {
        CHECK(all_zero(e));
      } else {
        events.push_back(e);
      }
    }
    REQUIRE(events.size() == 2U);
    const observed_access& h = events[0];
    CHECK(h.kind == observed_kind::header);
    CHECK(h.slave_id == 3U);
    CHECK(h.address == 0x2AU);
    CHECK(h.write == write);
    CHECK(h.cts);
    CHECK(h.crc == hcrc);
    CHECK(h.crc_ok);
    CHECK(h.echo == (write ? 0x1U : 0x2U));
    CHECK(h.data == 0U);  // byte fields: none in a header
    CHECK(h.answer == 0U);
    CHECK(h.answer_crc == 0U);
    CHECK(!h.stop);
    CHECK(h.waits == 0U);
    const observed_access& b = events[1];
    CHECK(b.kind == observed_kind::byte);
    CHECK(b.slave_id == 3U);
    CHECK(b.address == 0x2AU);
    CHECK(b.write == write);
    CHECK(b.data == v);
    CHECK(b.crc == ref_crc4(v, 8));
    CHECK(b.crc_ok);
    CHECK(b.answer == v);
    CHECK(b.answer_crc == ref_crc4(v, 8));
    CHECK(!b.stop);
    CHECK(b.waits == 0U);
    CHECK(!b.cts);  // header fields: none in a byte
    CHECK(b.echo == 0U);
  }
}

TEST_CASE("observer: wait states are counted per byte, and none carry over into a new access") {
  // Slave 0, register 0x10: a header for a read, then per byte S slots (each answered 0 is a
  // wait state, the one answered 1 starts the data), 8 data and 4 CRC4 slots, P.
  const auto header = [](std::uint32_t address, std::string& cdm, std::string& cds) {
    cdm +=
        "11" + bits(0, 3) + bits(address, 7) + bits(ref_crc4((1U << 10U) | address, 11), 4) + "10";
    cds += std::string(16, '0') + "10";
  };
  const auto byte = [](std::uint8_t v, std::size_t waits, std::string& cdm, std::string& cds) {
    cdm += std::string(waits + 1U, '1') + std::string(12, '0') + "0";
    cds += std::string(waits, '0') + "1" + bits(v, 8) + bits(ref_crc4(v, 8), 4) + "0";
  };
  const auto waits_of_bytes = [](const std::string& cdm, const std::string& cds) {
    std::vector<std::size_t> waits;
    for (const observed_access& e : feed_observer(cdm, cds)) {
      if (e.kind == observed_kind::byte) {
        waits.push_back(e.waits);
      }
    }
    return waits;
  };
  // a sequential read of two bytes: 2 wait states before the first, none before the second
  std::string cdm(preamble_frames, '0');
  std::string cds(preamble_frames, '0');
  header(0x10, cdm, cds);
  byte(0x12, 2, cdm, cds);
  byte(0x34, 0, cdm, cds);
  cdm += "0";
  cds += "0";
  CHECK(waits_of_bytes(cdm, cds) == std::vector<std::size_t>{2, 0});
  // an access whose master gives up in a wait state (3 of them, then the preamble), and a
  // new access whose byte has no wait state
  cdm.assign(preamble_frames, '0');
  cds.assign(preamble_frames, '0');
  header(0x10, cdm, cds);
  cdm += "111" + std::string(preamble_frames, '0');
  cds += std::string(3 + preamble_frames, '0');
  header(0x11, cdm, cds);
  byte(0x56, 0, cdm, cds);
  cdm += "0";
  cds += "0";
  CHECK(waits_of_bytes(cdm, cds) == std::vector<std::size_t>{0});
}
