//! A set-associative cache with least-recently-used replacement, counting hits
//! and misses: the building block of the boards' memory paths ([`super::board`]).

/// A cache of `sets x ways` lines of `1 << line_shift` bytes, LRU in each set.
/// A fully associative cache is one set.
#[derive(Clone, Debug)]
pub struct Cache {
    line_shift: u32,
    sets: usize,
    ways: usize,
    /// Per set, its lines' tags from the most to the least recently used;
    /// `u64::MAX` is an empty way.
    tags: Vec<u64>,
    /// Accesses that found their line.
    pub hits: u64,
    /// Accesses that did not (the line was then filled).
    pub misses: u64,
}

impl Cache {
    /// An empty cache of `bytes` bytes in lines of `line` bytes, `ways`-way set
    /// associative.
    ///
    /// # Panics
    /// When `line` or the number of sets is not a power of two, or `bytes` is
    /// not a whole number of sets (a model's parameters, fixed in the source).
    #[must_use]
    pub fn new(bytes: usize, line: usize, ways: usize) -> Self {
        assert!(
            line.is_power_of_two() && ways > 0,
            "line {line}, ways {ways}"
        );
        assert!(
            bytes.is_multiple_of(line * ways),
            "{bytes} bytes in {ways} ways of {line}"
        );
        let sets = bytes / (line * ways);
        assert!(sets.is_power_of_two(), "{sets} sets");
        Self {
            line_shift: line.trailing_zeros(),
            sets,
            ways,
            tags: vec![u64::MAX; sets * ways],
            hits: 0,
            misses: 0,
        }
    }

    /// The line size in bytes.
    #[must_use]
    pub fn line(&self) -> u64 {
        1 << self.line_shift
    }

    /// The line number of `addr` (its address without the offset in the line).
    #[must_use]
    pub fn line_of(&self, addr: u64) -> u64 {
        addr >> self.line_shift
    }

    /// Whether the line of `addr` is present, without touching the LRU order
    /// or the counts.
    #[must_use]
    pub fn holds(&self, addr: u64) -> bool {
        let line = self.line_of(addr);
        self.set(line).contains(&line)
    }

    fn set(&self, line: u64) -> &[u64] {
        let s = (line as usize) & (self.sets - 1);
        &self.tags[s * self.ways..(s + 1) * self.ways]
    }

    /// Looks `addr` up: a hit makes its line the most recently used; a miss
    /// fills the line in place of the set's least recently used one. Returns
    /// whether it hit.
    pub fn access(&mut self, addr: u64) -> bool {
        let hit = self.touch(addr, true);
        self.count(hit)
    }

    /// Looks `addr` up without filling it on a miss (a hit still counts and
    /// becomes the most recently used); returns whether it hit. For a path that
    /// fills only some misses ([`Cache::fill`] then).
    pub fn lookup(&mut self, addr: u64) -> bool {
        let hit = self.touch(addr, false);
        self.count(hit)
    }

    fn count(&mut self, hit: bool) -> bool {
        if hit {
            self.hits += 1;
        } else {
            self.misses += 1;
        }
        hit
    }

    /// Puts the line of `addr` in as the most recently used, without counting.
    pub fn fill(&mut self, addr: u64) {
        self.touch(addr, true);
    }

    fn touch(&mut self, addr: u64, fill: bool) -> bool {
        let line = self.line_of(addr);
        let s = (line as usize) & (self.sets - 1);
        let set = &mut self.tags[s * self.ways..(s + 1) * self.ways];
        match set.iter().position(|&t| t == line) {
            Some(i) => {
                set[..=i].rotate_right(1);
                true
            }
            None => {
                if fill {
                    set.rotate_right(1);
                    set[0] = line;
                }
                false
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sweep_misses_once_a_line() {
        // 1 KiB, 16-byte lines, 2 ways: 32 sets. Words read in order over
        // 512 bytes: one miss per line (32), the other three words hit.
        let mut c = Cache::new(1024, 16, 2);
        for a in (0..512).step_by(4) {
            c.access(a);
        }
        assert_eq!((c.misses, c.hits), (32, 96));
        // Again: all of it fits, all hits.
        for a in (0..512).step_by(4) {
            c.access(a);
        }
        assert_eq!((c.misses, c.hits), (32, 224));
    }

    #[test]
    fn lru_keeps_as_many_lines_of_a_set_as_it_has_ways() {
        // 2 ways, 32 sets of 16 bytes: addresses 512 bytes apart share a set.
        let mut c = Cache::new(1024, 16, 2);
        let (a, b, x) = (0, 512, 1024);
        // a, b fill the set; a, b hit; x evicts the least recent (a).
        for addr in [a, b, a, b, x] {
            c.access(addr);
        }
        assert_eq!((c.misses, c.hits), (3, 2));
        assert!(!c.holds(a) && c.holds(b) && c.holds(x));
        // b was used before x: touching b then loading a evicts x.
        c.access(b);
        c.access(a);
        assert!(c.holds(a) && c.holds(b) && !c.holds(x));
        // Three lines of one set in a loop thrash a 2-way LRU set: all misses.
        let mut c = Cache::new(1024, 16, 2);
        for _ in 0..10 {
            for addr in [a, b, x] {
                c.access(addr);
            }
        }
        assert_eq!((c.misses, c.hits), (30, 0));
        // The same loop in other sets: they do not disturb each other.
        let mut c = Cache::new(1024, 16, 2);
        for _ in 0..10 {
            for addr in [0, 16, 32] {
                c.access(addr);
            }
        }
        assert_eq!((c.misses, c.hits), (3, 27));
    }

    #[test]
    fn fully_associative_lru_is_one_set() {
        // 8 lines of 16 bytes (the F411's ART data cache): a loop over 8 lines
        // anywhere hits after its first round; over 9 it always misses.
        let mut c = Cache::new(128, 16, 8);
        let lines: Vec<u64> = (0..9).map(|i| i * 4096 + 16 * i).collect();
        for _ in 0..5 {
            for &l in &lines[..8] {
                c.access(l);
            }
        }
        assert_eq!((c.misses, c.hits), (8, 32));
        let mut c = Cache::new(128, 16, 8);
        for _ in 0..5 {
            for &l in &lines {
                c.access(l);
            }
        }
        assert_eq!((c.misses, c.hits), (45, 0));
    }

    #[test]
    fn lookup_does_not_fill() {
        let mut c = Cache::new(64, 8, 2);
        assert!(!c.lookup(0x100));
        assert!(!c.lookup(0x100));
        c.fill(0x100);
        assert!(c.lookup(0x104));
        assert_eq!((c.misses, c.hits), (2, 1));
    }
}
