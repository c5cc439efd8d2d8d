// motionbus firmware examples — the startup code of the Cortex-M boards (mps2_an386, microbit):
// the vector table and the reset handler, which copies .data, clears .bss, runs the static
// constructors and calls the image's main(). A board that takes the SysTick interrupt defines
// systick_handler(); otherwise it is the default handler.
#include <cstdint>

extern "C" {
extern std::uint32_t __data_load;
extern std::uint32_t __data_start;
extern std::uint32_t __data_end;
extern std::uint32_t __bss_start;
extern std::uint32_t __bss_end;
extern std::uint32_t __stack_top;
extern void (*__init_array_start)();
extern void (*__init_array_end)();
// The image's main(), called by its assembler name: C++ does not let a program call main.
int image_main() __asm__("main");

[[noreturn]] void reset_handler() {
  for (std::uint32_t *d = &__data_start, *s = &__data_load; d < &__data_end;) {
    *d++ = *s++;
  }
  for (std::uint32_t* b = &__bss_start; b < &__bss_end;) {
    *b++ = 0;
  }
  for (void (**f)() = &__init_array_start; f < &__init_array_end; ++f) {
    (*f)();
  }
  (void)image_main();
  for (;;) {
  }
}

void default_handler() {
  for (;;) {
  }
}

void systick_handler() __attribute__((weak, alias("default_handler")));

// The vector table: initial stack pointer, then the exception handlers (the entries the
// Cortex-M0 reserves are never taken there).
__attribute__((section(".vectors"), used)) void* const vectors[16] = {
    &__stack_top,
    reinterpret_cast<void*>(&reset_handler),
    reinterpret_cast<void*>(&default_handler),  // NMI
    reinterpret_cast<void*>(&default_handler),  // HardFault
    reinterpret_cast<void*>(&default_handler),  // MemManage (M3 and up)
    reinterpret_cast<void*>(&default_handler),  // BusFault (M3 and up)
    reinterpret_cast<void*>(&default_handler),  // UsageFault (M3 and up)
    nullptr,
    nullptr,
    nullptr,
    nullptr,
    reinterpret_cast<void*>(&default_handler),  // SVCall
    reinterpret_cast<void*>(&default_handler),  // DebugMonitor (M3 and up)
    nullptr,
    reinterpret_cast<void*>(&default_handler),  // PendSV
    reinterpret_cast<void*>(&systick_handler),  // SysTick
};
}
