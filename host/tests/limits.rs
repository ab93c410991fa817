//! Requests beyond a limit are refused at once, before any work or allocation,
//! with the figure they would need and the limit; a render of any accepted size
//! streams its PNG in bounded memory.

use crate::common::{bin, entries, scratch, temps, text};
use std::time::{Duration, Instant};

/// Runs the binary and checks that it refused quickly: exit `code`, no output
/// file; returns stderr.
fn refused(args: &[&str], code: i32) -> String {
    let dir = scratch("limits");
    let start = Instant::now();
    let out = bin().current_dir(&dir).args(args).output().unwrap();
    let took = start.elapsed();
    let e = text(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{args:?}: {e}");
    assert!(
        !e.contains("panicked") && !e.contains("memory allocation"),
        "{e}"
    );
    assert!(took < Duration::from_secs(3), "{args:?} took {took:?}");
    assert!(
        entries(&dir).is_empty(),
        "{args:?} wrote {:?}",
        entries(&dir)
    );
    e
}

#[test]
fn thread_counts_are_capped() {
    let e = refused(&["render", "--threads", "18446744073709551615"], 2);
    assert!(
        e.contains("18446744073709551615 render threads is more than the 256 allowed"),
        "{e}"
    );
    let e = refused(&["compare", "--threads", "257"], 2);
    assert!(e.contains("257 render threads"), "{e}");
}

#[test]
fn compare_and_trade_refuse_what_flip_cannot_measure_before_rendering() {
    let e = refused(&["compare", "--size", "8192x8192"], 1);
    assert!(
        e.contains("compare at 8192x8192: 67,108,864 pixels is more than the 28,537,988"),
        "{e}"
    );
    let e = refused(&["trade", "--size", "65535x65535"], 1);
    assert!(
        e.contains("trade at 65535x65535: 4,294,836,225 pixels"),
        "{e}"
    );
    let e = refused(&["trade", "--runs", "18446744073709551615"], 1);
    assert!(e.contains("at most 1000 timed runs"), "{e}");
}

#[test]
fn simulate_refuses_orbits_and_panels_beyond_its_limits() {
    let e = refused(&["simulate", "--orbit", "4000000000"], 1);
    assert!(
        e.contains("--orbit 4000000000: an orbit has 1 to 3600 frames"),
        "{e}"
    );
    let e = refused(&["simulate", "--size", "65535x65535"], 1);
    assert!(
        e.contains("64.0 GiB (68,717,379,600 bytes), more than the limit of 4.0 GiB"),
        "{e}"
    );
}

/// The peak resident memory of a running process, from /proc, in bytes.
fn peak_memory(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

#[test]
fn the_largest_render_streams_its_png_in_bounded_memory() {
    // 65535x65535 (12.9 GB of pixels): rows are compressed into the temporary
    // file as they are rendered, in a few MB. Stopped (SIGTERM: the temporary
    // file goes) once data has been written.
    let dir = scratch("huge");
    let mut child = bin()
        .current_dir(&dir)
        .args(["render", "--size", "65535x65535", "--sampler", "corner"])
        .args(["--tile", "16", "--threads", "2", "-o", "huge.png"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let mut size = 0;
    while size < 200_000 {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "only {size} bytes written"
        );
        assert!(child.try_wait().unwrap().is_none(), "the render ended");
        std::thread::sleep(Duration::from_millis(20));
        size = temps(&dir)
            .iter()
            .filter_map(|n| std::fs::metadata(dir.join(n)).ok())
            .map(|m| m.len())
            .sum();
    }
    let peak = peak_memory(child.id());
    let sent = std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    child.wait().unwrap();
    let peak = peak.expect("no /proc");
    assert!(peak < 200 << 20, "peak memory {peak} bytes");
    assert!(entries(&dir).is_empty(), "left: {:?}", entries(&dir));
}

/// Runs `args` to the end, reading its peak resident memory while it runs;
/// returns it (bytes) and the exit status.
fn peak_of(args: &[&str]) -> (u64, std::process::ExitStatus) {
    let dir = scratch("peak");
    let mut child = bin()
        .current_dir(&dir)
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut peak = 0;
    loop {
        // The high-water mark only grows: the last one read is the peak, but for
        // the last few milliseconds.
        if let Some(p) = peak_memory(child.id()) {
            peak = peak.max(p);
        }
        if let Some(status) = child.try_wait().unwrap() {
            return (peak, status);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// `compare` keeps the reference's f64 colours (24 bytes a pixel) and signature (8)
/// only while it makes its 8-bit image and silhouette band, and measures FLIP a
/// band of rows at a time: about 33 bytes a pixel at its peak, where keeping every
/// image whole would take about 103 (its images, their copies for FLIP, FLIP's 60
/// bytes a pixel of workspace): 2.93 GB at its largest size, 28.5 million pixels.
/// The sparse sampler's reference too: it keeps the two traced rows a row needs,
/// not the traced quarter of the frame.
#[test]
fn compare_peaks_at_about_33_bytes_a_pixel() {
    let (w, h) = (2400u64, 1600u64);
    let size = format!("{w}x{h}");
    for sampler in ["centre", "sparse"] {
        let args = [
            "compare",
            "chapter-direct",
            "--size",
            &size,
            "--sampler",
            sampler,
        ];
        let (peak, status) = peak_of(&args);
        assert!(status.success(), "{sampler}: {status}");
        let per_pixel = peak as f64 / (w * h) as f64;
        assert!(
            peak < 40 * w * h + (40 << 20),
            "{sampler}: peak {peak} bytes, {per_pixel:.1} a pixel"
        );
    }
}
