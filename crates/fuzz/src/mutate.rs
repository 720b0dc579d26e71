//! Mutations of text files in the ways hostile inputs differ from good
//! ones.

use rand_xoshiro::SplitMix64;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};

/// A small, seeded generator (rand_xoshiro's SplitMix64, the workspace's
/// one): campaigns are reproducible.
#[derive(Debug, Clone)]
pub struct Rng(SplitMix64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(SplitMix64::seed_from_u64(seed))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in `0..n` (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }
}

/// Numbers that break readers: huge, tiny, negative, not numbers at all,
/// and the counts just past the formats' limits.
const EXTREMES: &[&str] = &[
    "0",
    "-1",
    "-0",
    "1e308",
    "-1e308",
    "1e309",
    "5e-324",
    "1e-13",
    "NaN",
    "inf",
    "-inf",
    "4096",
    "65536",
    "999999999",
    "4294967296",
    "1e10",
    "-1e10",
    "3601",
    "10001",
    "0.0000001",
    "1.5",
    "",
    "x",
    "1,5",
    "2147483648",
    "1000001",
    "1e12",
    "1e13",
];

/// Junk inserted as it comes: Unicode, control characters, format
/// markers in the wrong place.
const JUNK: &[&str] = &[
    "°",
    "\u{0}",
    "\t",
    "TILT=NONE",
    "IESNA:LM-63-2002",
    "[",
    "]",
    "=",
    "\"",
    "{",
    "}",
    "\r",
    "\u{feff}",
    "é",
    "Ks",
    "f 1/-8 1",
    "mtllib m.mtl",
    "usemtl x",
    "[[part]]",
    // What word processors paste: line and paragraph separators, NEL.
    "\u{2028}",
    "\u{2029}",
    "\u{85}",
    // A word longer than any line.
    "WWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWW",
];

/// One mutation of `bytes`.
pub fn mutate(bytes: &[u8], rng: &mut Rng) -> Vec<u8> {
    let text = String::from_utf8_lossy(bytes).into_owned();
    let mut lines: Vec<String> = text.split('\n').map(str::to_owned).collect();
    match rng.below(9) {
        0..=2 => {
            // A number token becomes an extreme value.
            let numbered: Vec<usize> = (0..lines.len())
                .filter(|&i| lines[i].chars().any(|c| c.is_ascii_digit()))
                .collect();
            if let Some(&i) = numbered.get(rng.below(numbered.len().max(1))) {
                let tokens: Vec<String> = lines[i].split(' ').map(str::to_owned).collect();
                let numeric: Vec<usize> = (0..tokens.len())
                    .filter(|&k| tokens[k].chars().any(|c| c.is_ascii_digit()))
                    .collect();
                if let Some(&k) = numeric.get(rng.below(numeric.len().max(1))) {
                    let mut tokens = tokens;
                    // Keep what surrounds the number (a TOML key, a comma).
                    let t = &tokens[k];
                    let start = t.find(|c: char| c.is_ascii_digit() || c == '-' || c == '.');
                    let end = t.rfind(|c: char| c.is_ascii_digit() || c == '.');
                    if let (Some(a), Some(b)) = (start, end) {
                        let extreme = EXTREMES[rng.below(EXTREMES.len())];
                        tokens[k] = format!("{}{}{}", &t[..a], extreme, &t[b + 1..]);
                    }
                    lines[i] = tokens.join(" ");
                }
            }
        }
        3 if !lines.is_empty() => {
            let i = rng.below(lines.len());
            lines.remove(i);
        }
        4 if !lines.is_empty() => {
            // A line repeated, a few or many times.
            let i = rng.below(lines.len());
            let times = [1, 2, 10, 1000][rng.below(4)];
            let line = lines[i].clone();
            for _ in 0..times {
                lines.insert(i, line.clone());
            }
        }
        5 if lines.len() > 1 => {
            let (a, b) = (rng.below(lines.len()), rng.below(lines.len()));
            lines.swap(a, b);
        }
        6 => {
            let cut = rng.below(bytes.len() + 1);
            return bytes[..cut].to_vec();
        }
        7 if !lines.is_empty() => {
            let i = rng.below(lines.len());
            let at = rng.below(lines[i].len() + 1);
            let at = (0..=at)
                .rev()
                .find(|&k| lines[i].is_char_boundary(k))
                .unwrap_or(0);
            lines[i].insert_str(at, JUNK[rng.below(JUNK.len())]);
        }
        _ => {
            // Other line ends.
            let joined = lines.join("\n");
            return match rng.below(3) {
                0 => joined.replace('\n', "\r").into_bytes(),
                1 => joined.replace("\r\n", "\n").into_bytes(),
                _ => joined.replace('\n', "\r\n").into_bytes(),
            };
        }
    }
    lines.join("\n").into_bytes()
}
