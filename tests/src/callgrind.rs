//! The host's instruction profile: the release `tessera` binary rendering a
//! built-in scene on one thread under `valgrind --tool=callgrind`, total
//! instructions (`Ir`) and the top functions of `callgrind_annotate`.

use crate::firmware::{self, TempDir};
use std::path::PathBuf;
use std::process::Command;

/// One function of `callgrind_annotate`'s table.
#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    /// Instructions executed in it (self cost).
    pub ir: u64,
    /// Its share of the program's total, percent.
    pub percent: f64,
    /// The source file as printed (`???` when the binary has no line tables).
    pub file: String,
    /// The function.
    pub function: String,
}

/// One render under callgrind.
#[derive(Clone, Debug)]
pub struct HostProfile {
    /// The command line profiled.
    pub command: String,
    /// Instructions of the whole process (`summary:` of the callgrind file).
    pub total: u64,
    /// Rays traced, from the command's summary line.
    pub rays: u64,
    /// Pixels of the image, from the summary line (`scene: WxH, ...`).
    pub pixels: u64,
    /// The summary line.
    pub summary: String,
    /// The functions, most instructions first.
    pub functions: Vec<Function>,
}

/// The first line of `valgrind --version`, or `None` when valgrind is missing.
#[must_use]
pub fn valgrind_version() -> Option<String> {
    let out = Command::new("valgrind").arg("--version").output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Builds the release `tessera` binary (`cargo build --release -p tessera-host`)
/// and returns its path.
pub fn build_host() -> Result<PathBuf, String> {
    let root = firmware::repo_root();
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    firmware::checked(
        Command::new(cargo)
            .current_dir(&root)
            .args(["build", "--release", "-p", "tessera-host"]),
        "cargo to build tessera-host",
        "building tessera-host failed",
    )?;
    let dir =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    let bin = dir.join("release").join("tessera");
    if bin.is_file() {
        Ok(bin)
    } else {
        Err(format!("no binary at {}", bin.display()))
    }
}

/// Profiles `tessera render <scene> --threads 1` (the scene's own size and
/// settings) under callgrind.
pub fn profile(bin: &std::path::Path, scene: &str) -> Result<HostProfile, String> {
    let dir = TempDir::new()?;
    let cg = dir.path().join("callgrind.out");
    let png = dir.path().join("render.png");
    let args = ["render", scene, "--threads", "1", "-o"];
    let out = firmware::checked(
        Command::new("valgrind")
            .arg("--tool=callgrind")
            .arg(format!("--callgrind-out-file={}", cg.display()))
            .arg(bin)
            .args(args)
            .arg(&png),
        "valgrind",
        &format!("valgrind failed on {scene}"),
    )?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let summary = stdout
        .lines()
        .find(|l| l.contains(" rays"))
        .ok_or_else(|| format!("no summary line with the ray count in {stdout:?}"))?
        .trim()
        .to_string();
    let rays = rays(&summary).ok_or_else(|| format!("no ray count in {summary:?}"))?;
    let pixels = pixels(&summary).ok_or_else(|| format!("no image size in {summary:?}"))?;
    let text =
        std::fs::read_to_string(&cg).map_err(|e| format!("cannot read {}: {e}", cg.display()))?;
    let total = text
        .lines()
        .find_map(|l| l.strip_prefix("summary:"))
        .and_then(|v| v.trim().parse().ok())
        .ok_or("no `summary:` line in the callgrind output")?;
    let ann = Command::new("callgrind_annotate")
        .arg(&cg)
        .output()
        .map_err(|e| format!("cannot run callgrind_annotate: {e}"))?;
    if !ann.status.success() {
        return Err(format!("callgrind_annotate failed ({})", ann.status));
    }
    Ok(HostProfile {
        command: format!("tessera {} <out>.png", args[..4].join(" ")),
        total,
        rays,
        pixels,
        summary,
        functions: parse_annotate(&String::from_utf8_lossy(&ann.stdout)),
    })
}

/// The ray count of the summary line (`..., 126052 rays, 7.86 Mrays/s`).
#[must_use]
pub fn rays(summary: &str) -> Option<u64> {
    let words: Vec<&str> = summary.split_whitespace().collect();
    words
        .windows(2)
        .find(|w| w[1].trim_end_matches(',') == "rays")
        .and_then(|w| w[0].replace(',', "").parse().ok())
}

/// The pixels of the summary line (`chapter-reflect: 320x240, ...`).
#[must_use]
pub fn pixels(summary: &str) -> Option<u64> {
    summary.split_whitespace().find_map(|w| {
        let (a, b) = w.trim_end_matches(',').split_once('x')?;
        Some(a.parse::<u64>().ok()? * b.parse::<u64>().ok()?)
    })
}

/// The function lines of `callgrind_annotate`'s output:
/// `37,281,076 (33.62%)  ???:name [object]`.
#[must_use]
pub fn parse_annotate(text: &str) -> Vec<Function> {
    text.lines()
        .filter_map(|l| {
            let l = l.trim();
            let (ir, rest) = l.split_once(" (")?;
            let (pct, rest) = rest.split_once("%)")?;
            let name = rest.trim();
            if name == "PROGRAM TOTALS" || name.is_empty() {
                return None;
            }
            let name = name.rsplit_once(" [").map_or(name, |(n, _)| n);
            // `file:function`: the first colon that is not half of a `::`.
            let b = name.as_bytes();
            let colon = (0..b.len()).find(|&k| {
                b[k] == b':' && b.get(k + 1) != Some(&b':') && (k == 0 || b[k - 1] != b':')
            });
            let (file, function) = match colon {
                Some(k) => (&name[..k], &name[k + 1..]),
                None => ("", name),
            };
            Some(Function {
                ir: ir.replace(',', "").parse().ok()?,
                percent: pct.trim().parse().ok()?,
                file: file.to_string(),
                function: function.to_string(),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_ray_count_and_the_annotation() {
        let s = "chapter-reflect: 320x240, 1 sample(s)/px (centre), depth 1, 16x16 tiles, \
                 1 thread(s): 0.016 s, 126052 rays, 7.86 Mrays/s";
        assert_eq!(rays(s), Some(126_052));
        assert_eq!(pixels(s), Some(76_800));
        let ann = "--------\n\
                   110,899,701 (100.0%)  PROGRAM TOTALS\n\
                   --------\n\
                   Ir                   file:function\n\
                   37,281,076 (33.62%)  ???:<tessera_core::geometry::sphere::Sphere as tessera_core::geometry::Shape>::intersect [/x/tessera]\n\
                   \x20  604,657 ( 0.55%)  ./string/memmove.S:__memcpy_avx [/usr/lib/libc.so.6]\n";
        let f = parse_annotate(ann);
        assert_eq!(f.len(), 2);
        assert_eq!(f[0].ir, 37_281_076);
        assert!((f[0].percent - 33.62).abs() < 1e-9);
        assert_eq!(f[0].file, "???");
        assert_eq!(
            f[0].function,
            "<tessera_core::geometry::sphere::Sphere as tessera_core::geometry::Shape>::intersect"
        );
        assert_eq!(
            (f[1].file.as_str(), f[1].function.as_str()),
            ("./string/memmove.S", "__memcpy_avx")
        );
    }
}
