//! Case 13: surfaces far larger than their distance to the camera (a ground of two
//! triangles `10^7` wide seen from a few units, a wall, a tilted slope, the ground
//! as a sphere of radius `10^7`, a plane given by a point `10^7` away), rendered
//! by the core and by the f64 reference and compared with `tessera compare`'s
//! measure, for ratios of size over camera distance from `10^2` to `10^12`.
//!
//! Every number of the scenes is exact in `f32` (sizes rounded to 16 significant
//! bits, the surfaces through the world's origin with dyadic slopes), so that both
//! renderers see the same surfaces and the ratio is what the picture shows: a
//! vertex rounded by `f32` at `10^12` would move the surface by thousands of units.

use super::support::compared;
use tessera_core::Viewport;
use tessera_host::compare::Accuracy;
use tessera_host::desc::SceneDesc;

/// The ratios of the sweep (size over camera distance).
pub const HUGE_RATIOS: [f64; 16] = [
    1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17,
];

/// The viewport of case 13.
pub const HUGE_VIEWPORT: Viewport = Viewport::new(96, 72);

/// The surface of a case.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HugeSurface {
    /// A triangle in the ground plane `y = 0`.
    Floor,
    /// The ground `y = 0` as two triangles meeting under the camera (the usual
    /// way to write a ground: their shared edge passes near the view).
    Ground,
    /// A triangle in the plane `z = 0`, facing the camera.
    Upright,
    /// A triangle in the slope `x + 16 y + z / 2 = 0`.
    Tilted,
    /// A sphere of the size's radius whose top is the ground `y = 0`.
    Sphere,
    /// The slope as a `[[plane]]` given by a point the size away.
    Plane,
    /// A capped cylinder of the size's radius lying along `x`, from `-size` to
    /// `size`, whose top is the ground `y = 0`.
    Cylinder,
    /// The ground `y = 0` as a disk of the size's radius.
    Disk,
}

impl HugeSurface {
    /// Every surface.
    pub const ALL: [Self; 8] = [
        Self::Floor,
        Self::Ground,
        Self::Upright,
        Self::Tilted,
        Self::Sphere,
        Self::Plane,
        Self::Cylinder,
        Self::Disk,
    ];

    /// Its name in the report.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Floor => "floor triangle",
            Self::Ground => "ground of two triangles",
            Self::Upright => "upright triangle",
            Self::Tilted => "tilted triangle",
            Self::Sphere => "sphere",
            Self::Plane => "plane, far point",
            Self::Cylinder => "cylinder",
            Self::Disk => "disk",
        }
    }

    /// True for the single triangles, which take a [`Placement`].
    #[must_use]
    pub fn takes_placement(self) -> bool {
        matches!(self, Self::Floor | Self::Upright | Self::Tilted)
    }
}

/// Where a triangle lies around the point the camera looks at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// The triangle's vertices all the size away, around the view.
    Centre,
    /// One vertex a few units from the view, the others the size away.
    Vertex,
    /// One edge passing a fraction of a unit beside the camera's foot.
    Edge,
}

impl Placement {
    /// Every placement.
    pub const ALL: [Self; 3] = [Self::Centre, Self::Vertex, Self::Edge];

    /// Its name in the report.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Centre => "centre",
            Self::Vertex => "near a vertex",
            Self::Edge => "near an edge",
        }
    }
}

/// Every (surface, placement) of case 13: the single triangles at each
/// placement, the other surfaces at the centre.
#[must_use]
pub fn huge_cases() -> Vec<(HugeSurface, Placement)> {
    HugeSurface::ALL
        .into_iter()
        .flat_map(|s| {
            let placements: &[Placement] = if s.takes_placement() {
                &Placement::ALL
            } else {
                &[Placement::Centre]
            };
            placements.iter().map(move |&p| (s, p))
        })
        .collect()
}

/// Figures of one render of case 13.
#[derive(Clone, Debug)]
pub struct Huge {
    /// The size over the camera's distance to the surface (nominal: the size is
    /// rounded to 16 significant bits).
    pub ratio: f64,
    /// The largest difference outside the silhouette band, in 8-bit levels.
    pub max_outside: u8,
    /// The share of the pixels outside the band within 1 LSB.
    pub within1: f64,
    /// The share of the pixels that show the surface (not the background).
    pub covered: f64,
    /// The measure, whole.
    pub accuracy: Accuracy,
}

/// `x` rounded to 16 significant bits: exact in `f32`, and so are its sums and
/// halves up to 2^8 of it.
fn round16(x: f64) -> f64 {
    let e = x.abs().log2().floor() as i32 - 15;
    (x / 2f64.powi(e)).round() * 2f64.powi(e)
}

/// An `f64` that is exact in `f32`, written so that TOML reads it back exactly.
fn num(x: f64) -> String {
    assert_eq!(f64::from(x as f32), x, "{x} is not exact in f32");
    format!("{x:?}")
}

fn point(p: [f64; 3]) -> String {
    format!("[{}, {}, {}]", num(p[0]), num(p[1]), num(p[2]))
}

/// The scene of one case as a scene file's text.
#[must_use]
pub fn huge_scene(surface: HugeSurface, placement: Placement, ratio: f64) -> String {
    // The camera's distance to the surface: 2 above the ground and the slope, 6.1
    // in front of the wall.
    let distance = if surface == HugeSurface::Upright {
        6.1
    } else {
        2.0
    };
    let s = round16(ratio * distance);
    let (camera, look_at, ball) = match surface {
        HugeSurface::Upright => ([0.3, 1.2, 6.1], [0.0, 0.5, 0.0], [0.0, 0.5, 0.75]),
        _ => ([0.3, 2.0, 6.1], [0.0, 0.0, 0.0], [0.0, 0.75, 0.0]),
    };
    // The slope's height over (x, z); every vertex below is on it exactly.
    let slope = |x: f64, z: f64| -(x + z / 2.0) / 16.0;
    let on = |x: f64, z: f64| match surface {
        HugeSurface::Floor => [x, 0.0, z],
        HugeSurface::Upright => [x, -z, 0.0],
        _ => [x, slope(x, z), z],
    };
    let corners = match placement {
        Placement::Centre => [(-s, -s), (s, -s), (0.0, s)],
        Placement::Vertex => [(0.0, 8.0), (s / 2.0, -s), (-s / 2.0, -s)],
        Placement::Edge => [(0.0, s), (0.0, -s), (-s, 0.0)],
    };
    let body = match surface {
        HugeSurface::Sphere => format!(
            "[[sphere]]\ncenter = {}\nradius = {}\nmaterial = \"ground\"\n",
            point([0.0, -s, 0.0]),
            num(s)
        ),
        HugeSurface::Cylinder => format!(
            "[[cylinder]]\nbase = {}\ntop = {}\nradius = {}\nmaterial = \"ground\"\n",
            point([-s, -s, 0.0]),
            point([s, -s, 0.0]),
            num(s)
        ),
        HugeSurface::Disk => format!(
            "[[disk]]\ncenter = [0, 0, 0]\nnormal = [0, 1, 0]\nradius = {}\nmaterial = \"ground\"\n",
            num(s)
        ),
        HugeSurface::Plane => format!(
            "[[plane]]\npoint = {}\nnormal = [1, 16, 0.5]\nmaterial = \"ground\"\n",
            point([s, slope(s, 0.0), 0.0])
        ),
        HugeSurface::Ground => {
            let v = |x: f64, z: f64| point([x, 0.0, z]);
            let tri = |a: String, b: String, c: String| {
                format!("[[triangle]]\nvertices = [{a}, {b}, {c}]\nmaterial = \"ground\"\n")
            };
            tri(v(-s, -s), v(s, -s), v(s, s)) + &tri(v(-s, -s), v(s, s), v(-s, s))
        }
        _ => {
            let [a, b, c] = corners.map(|(x, z)| point(on(x, z)));
            format!("[[triangle]]\nvertices = [{a}, {b}, {c}]\nmaterial = \"ground\"\n")
        }
    };
    format!(
        "ambient = [0.1, 0.1, 0.1]\nbackground = [0.1, 0.2, 0.5]\n\n\
         [camera]\nposition = {camera:?}\nlook_at = {look_at:?}\nnear = 0.1\nfar = 100\n\n\
         [[material]]\nname = \"ground\"\ncolor = [0.7, 0.7, 0.7]\nspecular = 0.3\n\n\
         [[material]]\nname = \"ball\"\ncolor = [0.9, 0.2, 0.1]\nreflectivity = 0.3\n\n\
         [[sphere]]\ncenter = {ball:?}\nradius = 0.5\nmaterial = \"ball\"\n\n\
         [[light]]\nposition = [2, 6, 4]\nintensity = 40\n\n{body}"
    )
}

/// The description of one case.
#[must_use]
pub fn huge_desc(surface: HugeSurface, placement: Placement, ratio: f64) -> SceneDesc {
    let text = huge_scene(surface, placement, ratio);
    tessera_host::file::parse(&text, "case 13").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Case 13 for one surface, placement and ratio: the core against the reference.
#[must_use]
pub fn huge(surface: HugeSurface, placement: Placement, ratio: f64) -> Huge {
    let desc = huge_desc(surface, placement, ratio);
    let c = compared(&desc, HUGE_VIEWPORT).unwrap_or_else(|e| panic!("{e}"));
    let encoding = desc
        .settings()
        .map_or(tessera_core::Encoding::Srgb, |s| s.encoding);
    let sky = [0.1, 0.2, 0.5].map(|v| tessera_host::reference::encode8(v, encoding));
    let sky = c.reference.pixels().filter(|p| p.0 == sky).count();
    let covered = 1.0 - sky as f64 / f64::from(c.reference.width() * c.reference.height());
    let max_outside = c.accuracy.max_outside();
    let accuracy = c.accuracy;
    Huge {
        ratio,
        max_outside,
        within1: accuracy.share_within(1),
        covered,
        accuracy,
    }
}
