//! The memory paths of three boards, each with its parameters and where they
//! come from. A path returns the cycles an event stalls the core beyond a
//! zero-wait access; the cycle model ([`crate::cycles`]) counts the access
//! itself.

use super::cache::Cache;
use super::{Event, Kind, Mem, MemoryPath};

/// The RP2350 (Raspberry Pi Pico 2, two Cortex-M33 at 150 MHz).
///
/// - Flash is read through the XIP cache: 16 KiB, two-way set-associative,
///   8-byte lines, shared by instruction fetches and data loads (RP2350
///   datasheet, section 4.4, "External flash and PSRAM (XIP)"; pico-sdk's
///   `hardware/xip_cache.h`: `XIP_CACHE_SIZE`, `XIP_CACHE_LINE_SIZE`; `XIP_CTRL`'s
///   `SPLIT_WAYS`). The datasheet gives no replacement policy (modelled LRU) and
///   no hit latency (modelled zero-wait).
/// - A miss reads the line from the QSPI flash through the QMI, as the bootrom
///   leaves it (rp235x-hal and the Pico 2 example never change it): `EBh` quad
///   read sent without continuous-read mode, 4 dummy clocks, `CLKDIV` 3, so SCK =
///   50 MHz at 150 MHz (the bootrom's `varm_generic_flash.c` and
///   `BOOTROM_SPI_CLKDIV_FLASH_BOOT_MIN`; the register values read off a Pico 2
///   in pico-sdk issue 1903). An isolated miss costs [`Rp2350::MISS`]; a miss of
///   the line right after the last one missed, while the QMI still holds the
///   transfer open (`COOLDOWN`: 64 system cycles, modelled as at most 64
///   instructions since that miss) and not across a 1 KiB page, only its
///   data clocks, [`Rp2350::NEXT`].
/// - SRAM (520 KiB in ten banks, datasheet section 2.2) is zero-wait. Code run
///   from SRAM is fetched over the Cortex-M33's S-AHB port, which its own loads
///   and stores share; the stall that costs is not modelled (the count of
///   accesses that could collide is reported as a bound), nor are two cores
///   missing at once in the shared XIP cache.
pub struct Rp2350 {
    xip: Cache,
    /// The line of the last miss, and the instructions executed since.
    last_miss: Option<u64>,
    since_miss: u64,
}

impl Rp2350 {
    /// The board's flash address (XIP, cached).
    pub const FLASH: u64 = 0x1000_0000;
    /// Cycles at 150 MHz an isolated miss stalls the core: 8 SCK for the
    /// command (serial), 6 for 24 address bits and 2 for the mode byte on four
    /// lines, 4 dummy, 16 for 64 data bits on four lines: 36 SCK of 3 system
    /// cycles = 108, plus chip select, the receive delay and the bus, about 6.
    pub const MISS: u64 = 114;
    /// Cycles a miss of the next line costs while the transfer is open: its 16
    /// data clocks, 48 system cycles.
    pub const NEXT: u64 = 48;
    /// The QMI's cooldown window in system cycles (64 x `COOLDOWN` = 1),
    /// taken as 64 instructions (an instruction is at least a cycle: this
    /// counts a continued transfer where the chip may have closed it).
    const WINDOW: u64 = 64;
    /// The QMI's page: no transfer goes on across a 1 KiB boundary
    /// (`M0_TIMING.PAGEBREAK` as the bootrom sets it).
    const PAGE: u64 = 1024;

    /// The path as the bootrom leaves the flash.
    #[must_use]
    pub fn new() -> Self {
        Self {
            xip: Cache::new(16 * 1024, 8, 2),
            last_miss: None,
            since_miss: 0,
        }
    }

    /// The XIP cache.
    #[must_use]
    pub fn cache(&self) -> &Cache {
        &self.xip
    }
}

impl Default for Rp2350 {
    fn default() -> Self {
        Self::new()
    }
}

impl MemoryPath for Rp2350 {
    fn stall(&mut self, e: &Event, mem: Mem, addr: u64) -> u64 {
        let stall = match (mem, e.kind) {
            (Mem::Flash, Kind::Fetch | Kind::Load) if !self.xip.access(addr) => {
                let line = self.xip.line_of(addr);
                // The QMI ends a transfer at each 1 KiB page (`PAGEBREAK`).
                let next = self.last_miss.is_some_and(|l| l + 1 == line)
                    && self.since_miss <= Self::WINDOW
                    && !addr.is_multiple_of(Self::PAGE);
                self.last_miss = Some(line);
                self.since_miss = 0;
                if next { Self::NEXT } else { Self::MISS }
            }
            _ => 0,
        };
        // The event's instructions run after its fetch.
        if e.kind == Kind::Fetch {
            self.since_miss += u64::from(e.n);
        }
        stall
    }
}

/// The STM32F411 (Black Pill, one Cortex-M4F at 100 MHz, 3.3 V).
///
/// - Flash has [`Stm32f411::WAIT_STATES`] wait states at 100 MHz and is read 128
///   bits (16 bytes) at a time (RM0383, section 3.4, table 5, "Number of wait
///   states according to CPU clock (HCLK) frequency").
/// - The ART accelerator (RM0383, section 3.4.2, "Adaptive real-time memory
///   accelerator"): the instruction fetched is served from the current 128-bit
///   line, from the prefetched next line (prefetch on: the next sequential line
///   is read while the current one executes), or from the instruction cache of
///   64 lines of 128 bits; anything else is a miss, read from flash and copied
///   into the cache, whose lines are replaced least recently used first. Loads
///   from flash (literal pools, read-only data) go over the D-code bus through a
///   data cache of 8 lines of 128 bits that works the same way. The manual gives
///   no sets for either cache: they are modelled fully associative.
/// - A miss stalls the core by the wait states; a sequential line that was
///   prefetched stalls by what of the flash's read time the previous line's
///   instructions did not cover (one cycle an instruction at least).
/// - stm32f4xx-hal's clock set-up (`rcc.freeze`) sets the latency and turns on
///   the prefetch buffer and both caches.
/// - SRAM is zero-wait. Code run from SRAM is fetched over the S-bus, which its
///   own loads and stores share; that contention is not modelled (optimistic).
pub struct Stm32f411 {
    icache: Cache,
    dcache: Cache,
    /// The 16-byte line the core fetches from, and the instructions it has
    /// executed from it so far.
    current: Option<u64>,
    in_current: u64,
    prefetch: bool,
    wait_states: u64,
}

impl Stm32f411 {
    /// The board's flash address.
    pub const FLASH: u64 = 0x0800_0000;
    /// Wait states at 100 MHz and 2.7 to 3.6 V (RM0383, table 5).
    pub const WAIT_STATES: u64 = 3;
    const LINE: u64 = 16;

    /// The path as stm32f4xx-hal sets it up: prefetch and both caches on.
    #[must_use]
    pub fn new() -> Self {
        Self::with(Self::WAIT_STATES, true)
    }

    /// The path with `wait_states` and the prefetch buffer on or off.
    #[must_use]
    pub fn with(wait_states: u64, prefetch: bool) -> Self {
        Self {
            icache: Cache::new(64 * 16, 16, 64),
            dcache: Cache::new(8 * 16, 16, 8),
            current: None,
            in_current: 0,
            prefetch,
            wait_states,
        }
    }

    /// The instruction cache.
    #[must_use]
    pub fn icache(&self) -> &Cache {
        &self.icache
    }

    /// The data cache.
    #[must_use]
    pub fn dcache(&self) -> &Cache {
        &self.dcache
    }

    fn fetch(&mut self, addr: u64, n: u64) -> u64 {
        let line = addr / Self::LINE;
        let stall = match self.current {
            Some(c) if c == line => 0,
            current => {
                let stall = if self.icache.lookup(addr) {
                    0
                } else if self.prefetch && current == Some(line.wrapping_sub(1)) {
                    // The next line was read while the previous one ran.
                    (self.wait_states + 1).saturating_sub(self.in_current)
                } else {
                    self.icache.fill(addr);
                    self.wait_states
                };
                self.current = Some(line);
                self.in_current = 0;
                stall
            }
        };
        self.in_current += n;
        stall
    }
}

impl Default for Stm32f411 {
    fn default() -> Self {
        Self::new()
    }
}

impl MemoryPath for Stm32f411 {
    fn stall(&mut self, e: &Event, mem: Mem, addr: u64) -> u64 {
        match (mem, e.kind) {
            (Mem::Flash, Kind::Fetch) => self.fetch(addr, u64::from(e.n)),
            (Mem::Flash, Kind::Load) if !self.dcache.access(addr) => self.wait_states,
            (Mem::Ram, Kind::Fetch) => {
                // Leaving flash: the fetch line is no longer the current one.
                self.current = None;
                0
            }
            _ => 0,
        }
    }
}

/// The i.MX RT1062 (Teensy 4.1, one Cortex-M7 at 600 MHz).
///
/// - The tightly coupled memories run at the core's clock with no wait state
///   (i.MX RT1060 reference manual, chapter 31, FlexRAM; Cortex-M7 Technical
///   Reference Manual, section 5.1).
/// - teensy4-bsp links through imxrt-rt with 6 FlexRAM banks of ITCM and 10 of
///   DTCM: code in ITCM, data, `.bss` and the stack in DTCM, but `.rodata` in
///   OCRAM (imxrt-rt's `RuntimeBuilder::from_flexspi` default, which the BSP's
///   build script does not override), and it leaves the Cortex-M7's caches off
///   (its changelog). That is [`super::Layout::CodeInRam`] here, where what is
///   not in RAM is OCRAM: every load of read-only data (the scene's tables, the
///   sRGB table) is an uncached OCRAM read over the AXI bus, modelled at
///   [`Imxrt1062::OCRAM_LOAD`] cycles; two loads of one 8-byte granule in a row
///   count once (the stream merges them), so this is a lower bound.
/// - [`super::Layout::AllInRam`] (`.rodata` in DTCM, one line of the runtime's
///   builder) costs nothing.
pub struct Imxrt1062 {
    ocram_load: u64,
}

impl Imxrt1062 {
    /// The address the stream's "flash" (here: OCRAM) is carried to.
    pub const OCRAM: u64 = 0x2020_0000;
    /// Cycles at 600 MHz an uncached OCRAM load stalls the core. NXP documents
    /// no figure; 6 is an assumption (a 64-bit AXI read at a quarter of the
    /// core's clock, plus the bus), to be measured with the bench.
    pub const OCRAM_LOAD: u64 = 6;

    /// The path under teensy4-bsp's defaults.
    #[must_use]
    pub fn new() -> Self {
        Self {
            ocram_load: Self::OCRAM_LOAD,
        }
    }
}

impl Default for Imxrt1062 {
    fn default() -> Self {
        Self::new()
    }
}

impl MemoryPath for Imxrt1062 {
    fn stall(&mut self, e: &Event, mem: Mem, _addr: u64) -> u64 {
        match (mem, e.kind) {
            (Mem::Flash, Kind::Load) => self.ocram_load,
            _ => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fetch(addr: u64, n: u32) -> Event {
        Event {
            addr: addr as u32,
            kind: Kind::Fetch,
            n,
        }
    }

    fn load(addr: u64) -> Event {
        Event {
            addr: addr as u32,
            kind: Kind::Load,
            n: 4,
        }
    }

    #[test]
    fn rp2350_misses_once_per_line_of_a_loop_that_fits() {
        // A loop over 4 KiB of code, 8-byte granules of two instructions, run 10
        // times: 512 misses the first time, none after.
        let mut p = Rp2350::new();
        let mut stalls = 0;
        for _ in 0..10 {
            for a in (0..4096).step_by(8) {
                stalls += p.stall(&fetch(Rp2350::FLASH + a, 2), Mem::Flash, Rp2350::FLASH + a);
            }
        }
        assert_eq!((p.cache().misses, p.cache().hits), (512, 5120 - 512));
        // Each 1 KiB page starts a new transfer: 4 isolated misses, 508 that
        // continue one.
        assert_eq!(stalls, 4 * Rp2350::MISS + 508 * Rp2350::NEXT);
        // SRAM, and stores, cost nothing and do not touch the cache.
        assert_eq!(p.stall(&load(0x2000_0000), Mem::Ram, 0x2000_0000), 0);
        let store = Event {
            kind: Kind::Store,
            ..load(Rp2350::FLASH)
        };
        assert_eq!(p.stall(&store, Mem::Flash, Rp2350::FLASH), 0);
        assert_eq!(p.cache().misses + p.cache().hits, 5120);
    }

    #[test]
    fn rp2350_next_line_only_while_the_transfer_is_open() {
        let f = Rp2350::FLASH;
        // Line 1 after line 0 with 64 instructions between: the transfer is
        // still open; with 65 it has closed.
        let mut p = Rp2350::new();
        assert_eq!(p.stall(&fetch(f, 64), Mem::Flash, f), Rp2350::MISS);
        assert_eq!(p.stall(&fetch(f + 8, 1), Mem::Flash, f + 8), Rp2350::NEXT);
        let mut p = Rp2350::new();
        assert_eq!(p.stall(&fetch(f, 65), Mem::Flash, f), Rp2350::MISS);
        assert_eq!(p.stall(&fetch(f + 8, 1), Mem::Flash, f + 8), Rp2350::MISS);
        // A jump forward two lines: isolated.
        let mut p = Rp2350::new();
        p.stall(&fetch(f, 1), Mem::Flash, f);
        assert_eq!(p.stall(&fetch(f + 16, 1), Mem::Flash, f + 16), Rp2350::MISS);
    }

    #[test]
    fn rp2350_thrashes_beyond_its_ways() {
        // Three granules 8 KiB apart share a set of the two-way 16 KiB cache:
        // fetches and loads compete in it, and the loop misses every time.
        let mut p = Rp2350::new();
        let base = Rp2350::FLASH;
        let mut stalls = 0;
        for _ in 0..4 {
            stalls += p.stall(&fetch(base, 1), Mem::Flash, base);
            stalls += p.stall(&fetch(base + 0x2000, 1), Mem::Flash, base + 0x2000);
            stalls += p.stall(&load(base + 0x4000), Mem::Flash, base + 0x4000);
        }
        assert_eq!(stalls, 12 * Rp2350::MISS);
        // Two of them fit: one miss each, then hits.
        let mut p = Rp2350::new();
        let mut stalls = 0;
        for _ in 0..4 {
            stalls += p.stall(&fetch(base, 1), Mem::Flash, base);
            stalls += p.stall(&load(base + 0x2000), Mem::Flash, base + 0x2000);
        }
        assert_eq!(stalls, 2 * Rp2350::MISS);
    }

    #[test]
    fn f411_prefetch_hides_straight_code_and_the_cache_holds_loops() {
        let f = Stm32f411::FLASH;
        // Straight code, 4 instructions a 16-byte line (two granule events of
        // 2): the first line misses (3 wait states), the next ones come
        // prefetched in time (4 instructions >= 4 cycles of a read).
        let mut p = Stm32f411::new();
        let mut stalls = 0;
        for a in (0..256).step_by(8) {
            stalls += p.stall(&fetch(f + a, 2), Mem::Flash, f + a);
        }
        assert_eq!(stalls, 3);
        // With one instruction a line, the prefetch is late by 3 cycles a line.
        let mut p = Stm32f411::new();
        let mut stalls = 0;
        for a in (0..256).step_by(16) {
            stalls += p.stall(&fetch(f + a, 1), Mem::Flash, f + a);
        }
        assert_eq!(stalls, 3 + 15 * 3);
        // Without prefetch, every new line waits (16 lines).
        let mut p = Stm32f411::with(3, false);
        let mut stalls = 0;
        for a in (0..256).step_by(8) {
            stalls += p.stall(&fetch(f + a, 2), Mem::Flash, f + a);
        }
        assert_eq!(stalls, 16 * 3);
        // A jump back to a line that missed before hits the cache.
        assert_eq!(p.stall(&fetch(f, 2), Mem::Flash, f), 0);
        // A loop jumping among 65 lines apart evicts them all from the 64-line
        // cache: every jump misses.
        let mut p = Stm32f411::new();
        let mut stalls = 0;
        for _ in 0..3 {
            for i in 0..65 {
                let a = f + i * 64;
                stalls += p.stall(&fetch(a, 3), Mem::Flash, a);
            }
        }
        assert_eq!(stalls, 3 * 65 * 3);
        assert_eq!(p.icache().misses, 3 * 65);
        // 64 of them fit: misses the first round only.
        let mut p = Stm32f411::new();
        let mut stalls = 0;
        for _ in 0..3 {
            for i in 0..64 {
                let a = f + i * 64;
                stalls += p.stall(&fetch(a, 3), Mem::Flash, a);
            }
        }
        assert_eq!(stalls, 64 * 3);
    }

    #[test]
    fn f411_data_cache_holds_eight_lines() {
        let f = Stm32f411::FLASH + 0x1_0000;
        let mut p = Stm32f411::new();
        let mut stalls = 0;
        for _ in 0..4 {
            for i in 0..8 {
                stalls += p.stall(&load(f + i * 16), Mem::Flash, f + i * 16);
            }
        }
        assert_eq!(stalls, 8 * 3);
        let mut p = Stm32f411::new();
        let mut stalls = 0;
        for _ in 0..4 {
            for i in 0..9 {
                stalls += p.stall(&load(f + i * 16), Mem::Flash, f + i * 16);
            }
        }
        assert_eq!(stalls, 4 * 9 * 3);
        assert_eq!(p.dcache().misses, 36);
        // RAM: never a stall.
        assert_eq!(p.stall(&load(0x2000_0000), Mem::Ram, 0x2000_0000), 0);
    }

    #[test]
    fn imxrt_tcm_is_free_and_ocram_loads_cost() {
        let mut p = Imxrt1062::new();
        assert_eq!(p.stall(&fetch(0, 4), Mem::Ram, 0), 0);
        assert_eq!(p.stall(&load(0x2000_0000), Mem::Ram, 0x2000_0000), 0);
        let o = Imxrt1062::OCRAM;
        let stalls: u64 = (0..100)
            .map(|i| p.stall(&load(o + 8 * i), Mem::Flash, o + 8 * i))
            .sum();
        assert_eq!(stalls, 100 * Imxrt1062::OCRAM_LOAD);
    }
}
