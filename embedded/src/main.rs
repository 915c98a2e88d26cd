//! The firmware: the loop of `lib.rs` on a Cortex-M4F (QEMU's mps2-an386), the lines
//! and the digest printed through semihosting, then the instruction counts of the
//! controller step (SysTick under `qemu -icount shift=0`, where one instruction takes
//! one nanosecond of virtual time; calibrated on a loop of known length), then exit.
#![no_std]
#![no_main]

use core::fmt::Write;
use cortex_m::peripheral::{syst::SystClkSource, SYST};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio};
use rhonn_firmware::{run, write_line, Digest, Part, Regulation, PERIODS, PRINT_EVERY};

/// A line buffer on the stack (semihosting writes it in one call).
struct Line {
    buf: [u8; 384],
    len: usize,
}

impl Write for Line {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let b = s.as_bytes();
        let end = self.len + b.len();
        if end > self.buf.len() {
            return Err(core::fmt::Error);
        }
        self.buf[self.len..end].copy_from_slice(b);
        self.len = end;
        Ok(())
    }
}

impl Line {
    fn new() -> Self {
        Line {
            buf: [0; 384],
            len: 0,
        }
    }
    fn emit(&mut self, out: &mut hio::HostStream) {
        let _ = self.write_str("\n");
        let _ = out.write_all(&self.buf[..self.len]);
        self.len = 0;
    }
}

/// SysTick ticks elapsed while `f` runs (the counter counts down from 2^24 - 1).
fn ticks(_syst: &SYST, f: &mut dyn FnMut()) -> u32 {
    let start = SYST::get_current();
    f();
    let end = SYST::get_current();
    start.wrapping_sub(end) & 0x00ff_ffff
}

/// Instructions per SysTick tick: 200 `nop`s in a row (one `.rept` block, short enough
/// for the function's literal pool to stay in reach), run 100 times (the outer loop adds
/// a few instructions per 200).
#[inline(never)]
fn calibrate(syst: &SYST) -> f64 {
    let t = ticks(syst, &mut || {
        // An opaque count, or the compiler would unroll 20 copies of the block.
        for _ in 0..core::hint::black_box(100) {
            // SAFETY: `nop`s only: no memory, registers or flags are touched.
            unsafe {
                core::arch::asm!(
                    ".rept 200",
                    "nop",
                    ".endr",
                    options(nomem, nostack, preserves_flags)
                )
            };
        }
    });
    20_000.0 / t as f64
}

/// Exit QEMU with a failure status.
fn fail() -> ! {
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}

/// A panic prints its message and fails the run (QEMU exits with a non-zero status).
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    if let Ok(mut out) = hio::hstderr() {
        let _ = writeln!(out, "panic: {info}");
    }
    fail()
}

/// The stack's paint: words below the stack pointer are set to it at the start, and the
/// lowest word that no longer holds it at the end is the stack's high-water mark.
const PAINT: u32 = 0xDEAD_BEEF;

extern "C" {
    /// The first free word after the static data (cortex-m-rt's linker script).
    static mut __sheap: u32;
    /// The top of the stack (cortex-m-rt's linker script).
    static _stack_start: u32;
}

/// Paint the free RAM between the static data and 256 bytes below the stack pointer.
fn paint_stack() {
    let sp = cortex_m::register::msp::read() as usize;
    // SAFETY: the words from `__sheap` up to 256 bytes below the stack pointer are free
    // RAM (no heap; the stack grows down from above them), written with volatile stores.
    unsafe {
        let mut p = core::ptr::addr_of_mut!(__sheap);
        while (p as usize) < sp - 256 {
            p.write_volatile(PAINT);
            p = p.add(1);
        }
    }
}

/// The most stack used since [`paint_stack`] \[bytes\].
fn stack_used() -> usize {
    // SAFETY: reads of the painted free RAM (see `paint_stack`), volatile.
    unsafe {
        let top = core::ptr::addr_of!(_stack_start) as usize;
        let mut p = core::ptr::addr_of!(__sheap);
        while (p as usize) < top && p.read_volatile() == PAINT {
            p = p.add(1);
        }
        top - p as usize
    }
}

#[entry]
fn main() -> ! {
    paint_stack();
    let Ok(mut out) = hio::hstdout() else { fail() };
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        fail()
    };
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(0x00ff_ffff);
    cp.SYST.clear_current();
    cp.SYST.enable_counter();
    let syst = &cp.SYST;
    let per_tick = calibrate(syst);
    let mut digest = Digest::default();
    let mut regulation = Regulation::default();
    let mut line = Line::new();
    // Per part (controller, identifier) and for the whole step: total and worst ticks.
    let mut parts = [(0u64, 0u32); 3];
    let mut step_ticks = 0u32;
    let mut n = 0u32;
    let done = run(
        |s| {
            digest.add(s);
            regulation.add(s);
            if s.k % PRINT_EVERY == 0 || s.k + 1 == PERIODS {
                let _ = write_line(&mut line, s);
                line.emit(&mut out);
            }
        },
        |part, step| {
            let t = ticks(syst, step);
            let i = match part {
                Part::Controller => 0,
                Part::Identifier => 1,
            };
            parts[i] = (parts[i].0 + t as u64, parts[i].1.max(t));
            step_ticks = if i == 0 { t } else { step_ticks + t };
            if part == Part::Identifier {
                // The step ends with the identifier: count the whole.
                parts[2] = (parts[2].0 + step_ticks as u64, parts[2].1.max(step_ticks));
                n += 1;
            }
        },
    );
    if let Err(e) = done {
        let _ = write!(line, "firmware: {e}");
        line.emit(&mut out);
        fail()
    }
    let _ = write!(line, "digest={:016x}", digest.0);
    line.emit(&mut out);
    let _ = write!(
        line,
        "regulation rms_error_mpa={:.6} max_abs_error_mpa={:.6} (from 1 s after each set-point change)",
        regulation.rms_mpa(),
        regulation.max_abs_mpa
    );
    line.emit(&mut out);
    let _ = write!(
        line,
        "online_identifier rms_error_mpa={:.6} persistence_rms_error_mpa={:.6} (estimate minus the plant's pressure, 5 to 10 s)",
        regulation.online_rms_mpa(),
        regulation.persistence_rms_mpa()
    );
    line.emit(&mut out);
    for (i, name) in [
        "instructions_per_step",
        "controller_instructions",
        "identifier_instructions",
    ]
    .iter()
    .enumerate()
    {
        let (total, worst) = parts[[2, 0, 1][i]];
        let _ = write!(
            line,
            "{name} mean={:.0} max={:.0} per_tick={:.3}",
            total as f64 / n as f64 * per_tick,
            worst as f64 * per_tick,
            per_tick
        );
        line.emit(&mut out);
    }
    let _ = write!(line, "stack_bytes={}", stack_used());
    line.emit(&mut out);
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi();
    }
}
