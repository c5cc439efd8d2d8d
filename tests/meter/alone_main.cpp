// The image of the stream objects alone (tests/meter/meter.py, measure_alone()): each is in its
// own translation unit (alone_receiver.cpp, alone_framer.cpp, alone_gateway.cpp), as in a firmware
// whose receive interrupt's file holds nothing else; this one holds only what the meter reads and
// the entry.

#include <cstdint>

extern "C" {
__attribute__((used, aligned(8))) std::uint32_t meter_out[64];
// The image's entry (never run by the meter: it calls functions one at a time).
__attribute__((used)) void meter_entry() {}
}
