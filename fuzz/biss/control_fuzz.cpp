// BiSS-C control communication state machines fed arbitrary bits. Oracles: the master fed
// random CDS bits ends every access (done or failed) within its bound in frames, and a done
// read/write moved exactly the bytes asked for; the slave fed random CDM bits recovers: after
// 14 zero frames a real master reads and writes through it correctly; the observer fed random
// CDS/CDM pairs recovers too: after the preamble it reports exactly the headers and bytes of
// that exchange.

// fuzz-max-len: 512 (4 option bytes, then 4064 bits: the master's longest access, 4 bytes with
// 32 wait frames each, is 221 frames (frames_for(4) + 4 x 33), 18 of them; the slave and the
// observer take two bits a frame, 2032 frames: 9 such accesses. A longer stream only repeats
// their states)
#include <motionbus/biss/control.hpp>

#include <array>
#include <cstddef>
#include <cstdint>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace bs = motionbus::biss;

namespace {

struct registers {
  std::array<std::uint8_t, 128> mem{};
  int busy = 0;
  int write_delay = 0;
  bool readable(std::uint8_t a) const { return a != 0x50; }
  bool writable(std::uint8_t a) const { return a >= 0x40 && a != 0x50; }
  bool ready() const { return busy == 0; }
  std::uint8_t read(std::uint8_t a) { return mem[a]; }
  void write(std::uint8_t a, std::uint8_t v) {
    mem[a] = v;
    busy = write_delay;
  }
  void tick() {
    if (busy > 0) {
      --busy;
    }
  }
};

class bits {
 public:
  bits(const std::uint8_t* d, std::size_t n) : d_(d), n_(n) {}
  bool more() const { return i_ < n_ * 8U; }
  bool next() {
    const bool b = more() && ((d_[i_ / 8U] >> (i_ % 8U)) & 1U) != 0U;
    ++i_;
    return b;
  }

 private:
  const std::uint8_t* d_;
  std::size_t n_;
  std::size_t i_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 4) {
    return 0;
  }
  const auto id = static_cast<std::uint8_t>(data[0] & 7U);
  const auto address = static_cast<std::uint8_t>(data[1] & 0x7FU);
  const std::size_t count = 1U + data[2] % 4U;
  const bool write = (data[3] & 1U) != 0U;
  bs::control_options opt;
  opt.max_wait_frames = 1U + data[3] % 32U;

  // 1. the master against random CDS bits
  {
    bs::control_master m(opt);
    std::uint8_t buffer[4] = {0x11, 0x22, 0x33, 0x44};
    const mb::errc e = write ? m.start_write(id, address, mb::byte_view(buffer, count))
                             : m.start_read(id, address, mb::mutable_byte_view(buffer, count));
    if (e == mb::errc::ok) {
      bits in(data + 4, size - 4);
      const std::size_t bound =
          bs::control_master::frames_for(count) + count * (opt.max_wait_frames + 1U);
      std::size_t frames = 0;
      while (m.busy() && in.more()) {
        (void)m.step(in.next());
        ++frames;
        MOTIONBUS_FUZZ_CHECK(frames <= bound);
      }
      if (m.state() == bs::control_state::done) {
        MOTIONBUS_FUZZ_CHECK(m.transferred() == count && m.error() == mb::errc::ok);
      }
      if (m.state() == bs::control_state::failed) {
        MOTIONBUS_FUZZ_CHECK(m.error() != mb::errc::ok && m.transferred() < count);
      }
    } else {
      MOTIONBUS_FUZZ_CHECK(e == mb::errc::invalid_argument);
    }
  }

  // 2. the slave against random CDM bits, then a real exchange
  {
    registers regs;
    regs.write_delay = data[3] % 8U;
    for (unsigned a = 0; a < 128; ++a) {
      regs.mem[a] = static_cast<std::uint8_t>(a ^ 0x5AU);
    }
    bs::control_slave<registers> s(regs, {id, false});
    bs::control_observer obs;
    bits in(data + 4, size - 4);
    while (in.more()) {
      const bool cdm = in.next();
      (void)obs.step(s.step(cdm), in.next());
      regs.tick();
    }
    std::array<bs::observed_access, 8> seen{};
    std::size_t n_seen = 0;
    const auto tap = [&](bool frame_cds, bool cdm) {
      const bs::observed_access e = obs.step(frame_cds, cdm);
      if (e.kind != bs::observed_kind::none) {
        MOTIONBUS_FUZZ_CHECK(n_seen < seen.size());
        seen[n_seen++] = e;
      }
    };
    bs::control_master m;  // default bound: enough for the write delays here
    const auto base = static_cast<std::uint8_t>(0x58U + address % 0x20U);  // writable, not 0x50
    const std::uint8_t to_write[2] = {static_cast<std::uint8_t>(data[2]),
                                      static_cast<std::uint8_t>(~data[2])};
    MOTIONBUS_FUZZ_CHECK(m.start_write(id, base, mb::byte_view(to_write, 2)) == mb::errc::ok);
    bool cds = false;
    for (std::size_t k = 0; k < 14; ++k) {  // the master's own preamble is only counted by it
      tap(cds, false);
      cds = s.step(false);
      regs.tick();
    }
    n_seen = 0;  // what the random bits left half-seen may complete during the preamble
    const auto exchange = [&]() {
      while (m.busy()) {
        const bool cdm = m.step(cds);
        tap(cds, cdm);
        cds = s.step(cdm);
        regs.tick();
      }
    };
    const auto check_access = [&](bool write_access, const std::uint8_t* bytes, std::size_t n) {
      MOTIONBUS_FUZZ_CHECK(n_seen == n + 1U);
      const bs::observed_access& h = seen[0];
      MOTIONBUS_FUZZ_CHECK(h.kind == bs::observed_kind::header && h.slave_id == id &&
                           h.address == base && h.write == write_access && h.crc_ok &&
                           h.echo == (write_access ? 1U : 2U));
      for (std::size_t i = 0; i < n; ++i) {
        const bs::observed_access& b = seen[i + 1U];
        MOTIONBUS_FUZZ_CHECK(b.kind == bs::observed_kind::byte && b.address == base + i &&
                             b.data == bytes[i] && b.crc_ok && !b.stop);
      }
      n_seen = 0;
    };
    exchange();
    MOTIONBUS_FUZZ_CHECK(m.state() == bs::control_state::done);
    MOTIONBUS_FUZZ_CHECK(regs.mem[base] == to_write[0] && regs.mem[base + 1U] == to_write[1]);
    check_access(true, to_write, 2);
    std::uint8_t back[3] = {};
    MOTIONBUS_FUZZ_CHECK(m.start_read(id, base, mb::mutable_byte_view(back, 3)) == mb::errc::ok);
    exchange();
    MOTIONBUS_FUZZ_CHECK(m.state() == bs::control_state::done);
    MOTIONBUS_FUZZ_CHECK(back[0] == to_write[0] && back[1] == to_write[1] &&
                         back[2] == regs.mem[base + 2U]);
    check_access(false, back, 3);
  }
  return 0;
}
