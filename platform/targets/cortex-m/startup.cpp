// Start-up of the bare-metal image (Cortex-M7, linker script mps2_an500.ld): the
// vector table, and a reset handler that enables the FPU, copies .data, zeroes
// .bss, runs the static constructors and calls main().
#include <cstdint>

#include "fg/platform/board.h"

#ifdef FG_SEMIHOSTING
#include "semihosting.hpp"
#endif

extern "C" {
// From the linker script.
extern uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[], _estack[];
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();

int main();
[[noreturn]] void Reset_Handler();
[[noreturn]] void Default_Handler();
}

namespace {

volatile uint32_t& reg(uintptr_t address) { return *reinterpret_cast<volatile uint32_t*>(address); }
constexpr uintptr_t kCpacr = 0xE000ED88u;  // coprocessor access control

[[noreturn]] void stop(bool ok) {
#ifdef FG_SEMIHOSTING
  fg::cortex_m::semihost_exit(ok);  // ends the QEMU run with main()'s verdict
#else
  (void)ok;
  for (;;) __asm__ __volatile__("wfi");
#endif
}

}  // namespace

extern "C" void Reset_Handler() {
  // Full access to CP10/CP11 (the FPU) before any floating-point instruction: the
  // code is built for the hard-float ABI.
  reg(kCpacr) |= 0xFu << 20;
  __asm__ __volatile__("dsb\n\tisb" ::: "memory");

  for (uint32_t *src = _sidata, *dst = _sdata; dst < _edata;) *dst++ = *src++;
  for (uint32_t* dst = _sbss; dst < _ebss;) *dst++ = 0;
  for (void (**f)() = __init_array_start; f < __init_array_end; ++f) (*f)();

  stop(main() == 0);
}

extern "C" void Default_Handler() {
  fg_board_fault("startup.cpp", __LINE__, "unexpected exception (fault or interrupt)");
  stop(false);
}

// ARMv7-M vector table: initial stack pointer, then the system exceptions. The
// image enables no interrupt, so the device interrupts need no entries.
using Vector = void (*)();
__attribute__((section(".isr_vector"), used)) const Vector g_vectors[16] = {
    reinterpret_cast<Vector>(_estack),
    Reset_Handler,
    Default_Handler,  // NMI
    Default_Handler,  // HardFault
    Default_Handler,  // MemManage
    Default_Handler,  // BusFault
    Default_Handler,  // UsageFault
    nullptr,
    nullptr,
    nullptr,
    nullptr,
    Default_Handler,  // SVCall
    Default_Handler,  // DebugMonitor
    nullptr,
    Default_Handler,  // PendSV
    Default_Handler,  // SysTick
};
