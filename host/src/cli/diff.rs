//! `tessera diff`: two image files (PNG, PPM) compared pixel for pixel, with
//! compare's figures (no silhouette band: no scene), the differing pixels
//! counted and the largest listed, and compare's heat map when asked for one.

use super::Error;
use super::image_file::ImageFile;
use clap::{Args, ValueHint};
use image::RgbImage;
use std::path::PathBuf;
use tessera_host::output::{self, Input, Pending, Target};
use tessera_host::{HostError, compare, escape_path};

/// The differing pixels listed, largest first.
const LISTED: usize = 8;

#[derive(Args)]
pub struct DiffArgs {
    /// The first image (FLIP's reference): a PNG, or a PPM (P6 or P3, maxval 255)
    #[arg(value_name = "A", value_hint = ValueHint::FilePath)]
    a: PathBuf,
    /// The second image, of the same size: a PNG or a PPM
    #[arg(value_name = "B", value_hint = ValueHint::FilePath)]
    b: PathBuf,
    /// Also write a heat map of the differences to this PNG (none by default)
    #[arg(long, value_name = "FILE", value_hint = ValueHint::FilePath)]
    heatmap: Option<PathBuf>,
}

pub fn run(args: &DiffArgs) -> Result<(), Error> {
    let a = ImageFile::open(&args.a)?;
    let b = ImageFile::open(&args.b)?;
    let (w, h) = a.size();
    if a.size() != b.size() {
        let (bw, bh) = b.size();
        return Err(Error::SizesDiffer {
            a: (args.a.clone(), w, h),
            b: (args.b.clone(), bw, bh),
        });
    }
    // Checked and created before the pixels are read: an unwritable folder, or
    // a heat map that would replace an input, is known at once.
    let heatmap = match &args.heatmap {
        Some(path) => {
            let inputs = [&a, &b].map(|i| Input {
                path: i.path().to_path_buf(),
                what: format!("the input image {}", i.path().display()),
            });
            Some((path, Pending::create(Target::check(path, &inputs)?)?))
        }
        None => None,
    };
    let title = format!(
        "{} ({}) vs {} ({}): {w}x{h}",
        escape_path(&args.a),
        a.format(),
        escape_path(&args.b),
        b.format()
    );
    let (a, b) = (a.read()?, b.read()?);
    // compare's figures, A as the reference, with no band: every pixel counts.
    let acc = compare::measure_with_band(&b, 0, &a, 0, &[])?;
    let found = Differences::of(&a, &b);
    let pct = |x: f64| 100.0 * x;
    println!("{title}");
    println!("pixels                 {}", acc.pixels);
    println!("PSNR                   {:.2} dB", acc.psnr_db);
    println!("mean FLIP              {:.6}", acc.mean_flip);
    println!("max abs difference     {} LSB", acc.max_abs_diff);
    println!(
        "differing pixels       {} ({:.3}%)",
        found.count,
        pct(found.count as f64 / acc.pixels.max(1) as f64)
    );
    println!(
        "all pixels:   within 0 / 1 / 2 LSB, more: {:.3}% / {:.3}% / {:.3}%, {} px",
        pct(acc.share_within_all(0)),
        pct(acc.share_within_all(1)),
        pct(acc.share_within_all(2)),
        acc.all[3]
    );
    if !found.largest.is_empty() {
        let list: Vec<String> = found
            .largest
            .iter()
            .map(|d| {
                format!(
                    "({}, {}) {} LSB: {},{},{} vs {},{},{}",
                    d.x, d.y, d.by, d.a[0], d.a[1], d.a[2], d.b[0], d.b[1], d.b[2]
                )
            })
            .collect();
        println!("largest differences    {}", list.join("; "));
    }
    println!(
        "identical              {}",
        if found.count == 0 { "yes" } else { "no" }
    );
    if let Some((path, mut file)) = heatmap {
        let map = compare::heatmap_with_band(&b, &a, &[]);
        if let Err(e) = tessera_host::encode_png(&map, &mut file) {
            return Err(file.error(HostError::Write(e)).into());
        }
        output::commit(vec![file])?;
        println!(
            "wrote {} (black: equal, blue: 1 LSB, green: 2, yellow: 3-4, red: 5+)",
            escape_path(path)
        );
    }
    match found.largest.first() {
        None => Ok(()),
        Some(first) => Err(Error::ImagesDiffer {
            a: args.a.clone(),
            b: args.b.clone(),
            how: format!(
                "{} pixel(s) of {}, by up to {} LSB (the first of the largest at ({}, {}))",
                found.count, acc.pixels, acc.max_abs_diff, first.x, first.y
            ),
        }),
    }
}

/// A pixel that differs: where, by how much (its largest channel difference),
/// and its channels in A and B.
struct Difference {
    x: u32,
    y: u32,
    by: u8,
    a: [u8; 3],
    b: [u8; 3],
}

/// The pixels that differ between two images of the same size: how many, and
/// the [`LISTED`] largest differences, largest first (equal ones in row order).
struct Differences {
    count: u64,
    largest: Vec<Difference>,
}

impl Differences {
    fn of(a: &RgbImage, b: &RgbImage) -> Self {
        let mut count = 0;
        let mut largest: Vec<Difference> = Vec::with_capacity(LISTED + 1);
        for ((x, y, pa), pb) in a.enumerate_pixels().zip(b.pixels()) {
            let by =
                pa.0.iter()
                    .zip(pb.0)
                    .map(|(p, q)| p.abs_diff(q))
                    .max()
                    .unwrap_or(0);
            if by == 0 {
                continue;
            }
            count += 1;
            // After the equal ones already listed: they come first in row order.
            let at = largest.partition_point(|d| d.by >= by);
            if at < LISTED {
                largest.insert(
                    at,
                    Difference {
                        x,
                        y,
                        by,
                        a: pa.0,
                        b: pb.0,
                    },
                );
                largest.truncate(LISTED);
            }
        }
        Self { count, largest }
    }
}
