//! The core's error: a small `Copy` enum whose `Display` is the message a user reads.
//! Creating one never allocates.

use core::fmt;

/// Which number of the scene or settings an [`Error`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[allow(missing_docs)] // each variant's doc is its Display text below
#[non_exhaustive]
pub enum Field {
    CameraPosition,
    CameraForward,
    CameraUp,
    FieldOfView,
    Near,
    Far,
    SphereCenter,
    SphereRadius,
    PlanePoint,
    PlaneNormal,
    TriangleVertex,
    BoxMin,
    BoxMax,
    CylinderBase,
    CylinderTop,
    CylinderRadius,
    DiskCenter,
    DiskNormal,
    DiskRadius,
    DiskInnerRadius,
    Color,
    Ambient,
    Diffuse,
    Specular,
    Shininess,
    Reflectivity,
    Transparency,
    RefractiveIndex,
    TextureScale,
    FringeSpacing,
    TextureColor,
    LightPosition,
    LightColor,
    LightIntensity,
    LightDirection,
    ImageSize,
    ImageTexels,
    AmbientLight,
    Background,
    SubPixelOffset,
    RayOrigin,
    RayDirection,
    InstanceRotation,
    InstanceScale,
    InstanceTranslation,
    KeyframeTime,
    KeyframeValue,
}

impl Field {
    /// The name used in messages, e.g. `sphere radius`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::CameraPosition => "camera position",
            Self::CameraForward => "camera forward",
            Self::CameraUp => "camera up",
            Self::FieldOfView => "camera field of view",
            Self::Near => "camera near distance",
            Self::Far => "camera far distance",
            Self::SphereCenter => "sphere center",
            Self::SphereRadius => "sphere radius",
            Self::PlanePoint => "plane point",
            Self::PlaneNormal => "plane normal",
            Self::TriangleVertex => "triangle vertex",
            Self::BoxMin => "box min corner",
            Self::BoxMax => "box max corner",
            Self::CylinderBase => "cylinder base",
            Self::CylinderTop => "cylinder top",
            Self::CylinderRadius => "cylinder radius",
            Self::DiskCenter => "disk center",
            Self::DiskNormal => "disk normal",
            Self::DiskRadius => "disk radius",
            Self::DiskInnerRadius => "disk inner radius",
            Self::Color => "material color",
            Self::Ambient => "material ambient weight",
            Self::Diffuse => "material diffuse weight",
            Self::Specular => "material specular weight",
            Self::Shininess => "material shininess",
            Self::Reflectivity => "material reflectivity",
            Self::Transparency => "material transparency",
            Self::RefractiveIndex => "material refractive index",
            Self::TextureScale => "texture scale",
            Self::FringeSpacing => "fringe spacing",
            Self::TextureColor => "texture color",
            Self::LightPosition => "light position",
            Self::LightColor => "light color",
            Self::LightIntensity => "light intensity",
            Self::LightDirection => "light direction",
            Self::ImageSize => "image texture size",
            Self::ImageTexels => "image texture texels",
            Self::AmbientLight => "scene ambient light",
            Self::Background => "scene background",
            Self::SubPixelOffset => "sub-pixel offset",
            Self::RayOrigin => "ray origin",
            Self::RayDirection => "ray direction",
            Self::InstanceRotation => "instance rotation",
            Self::InstanceScale => "instance scale",
            Self::InstanceTranslation => "instance translation",
            Self::KeyframeTime => "keyframe time",
            Self::KeyframeValue => "keyframe value",
        }
    }
}

/// A scene list, named in capacity errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[allow(missing_docs)]
#[non_exhaustive]
pub enum List {
    Spheres,
    Planes,
    Triangles,
    Boxes,
    Cylinders,
    Disks,
    Materials,
    Lights,
    /// The nodes of a bounding volume hierarchy (`Bvh`, feature `bvh`).
    BvhNodes,
    /// The meshes of a scene view (`SceneView::with_meshes`, feature `bvh`).
    Meshes,
    /// The instances of a view's meshes (`Instances`, feature `instances`).
    Instances,
}

impl List {
    /// The list's name in messages.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Spheres => "spheres",
            Self::Planes => "planes",
            Self::Triangles => "triangles",
            Self::Boxes => "boxes",
            Self::Cylinders => "cylinders",
            Self::Disks => "disks",
            Self::Materials => "materials",
            Self::Lights => "lights",
            Self::BvhNodes => "BVH nodes",
            Self::Meshes => "meshes",
            Self::Instances => "instances",
        }
    }
}

/// Everything that can go wrong when building a camera, a scene or a frame, or when
/// rendering a tile. The `Display` text says what is wrong and which value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Error {
    /// A number is NaN or infinite.
    NotFinite(Field),
    /// A direction has zero length (or cannot be normalised).
    ZeroLength(Field),
    /// A number must be strictly positive.
    NotPositive(Field),
    /// A number is outside its range; `range` says which.
    OutOfRange {
        /// The value's name.
        field: Field,
        /// The accepted range, e.g. `"(0, 180) degrees"`.
        range: &'static str,
    },
    /// The near distance is not smaller than the far distance.
    NearNotBeforeFar,
    /// The viewport has no pixel (width or height 0).
    EmptyViewport,
    /// A primitive refers to a material that the scene does not have.
    MaterialOutOfRange {
        /// The material index asked for.
        id: u16,
        /// How many materials the scene has.
        count: u16,
    },
    /// A scene list is full.
    CapacityExceeded {
        /// Which list.
        list: List,
        /// Its capacity (the `const` parameter of the scene type).
        capacity: usize,
    },
    /// A triangle's three vertices are collinear (zero area).
    DegenerateTriangle,
    /// A `Bvh` (feature `bvh`) given to a scene view was not built from that scene's
    /// triangles (or not since they changed).
    BvhMismatch,
    /// A mesh (`Mesh`, feature `bvh`) does not hold together: a face's vertex index
    /// out of range, normals that are not one unit vector per vertex, 65,536 faces
    /// or more, a hierarchy of other faces, or a view that has meshes already.
    BadMesh,
    /// An instance (`Instance`, feature `instances`) of a mesh the view does
    /// not have.
    MeshOutOfRange {
        /// The mesh index asked for.
        id: u16,
        /// How many meshes the view has.
        count: u16,
    },
    /// A box's min corner is above its max corner on some axis.
    InvertedBox,
    /// The recursion depth asked for is above [`crate::error::MAX_DEPTH`].
    DepthTooLarge {
        /// The depth asked for.
        depth: u8,
    },
    /// A sampler with zero samples (stratified 0 or random 0), or more than 64x64
    /// (adaptive: fewer than 2x2 or more than 64x64).
    BadSampleCount,
    /// An adaptive or sparse sampler's threshold that is not an integer from 0 to 255.
    BadThreshold,
    /// A sparse sampler's spacing that is neither 2 nor 4 (`sparse:T,S`).
    BadSpacing,
    /// Sampler text that is none of `corner`, `centre`, `prefiltered`,
    /// `offset:X,Y`, `stratified:K`, `random:N`, `adaptive:K[,T]`.
    UnknownSampler,
    /// A tile coordinate outside the frame.
    TileOutOfFrame,
    /// The frame's settings and scene need a tile loop that the set of loops the
    /// firmware chose to link does not have ([`crate::tile::Loops`]).
    NotLinked,
    /// A material's reflectivity and transparency add up to more than 1: it would
    /// send on more light than it receives.
    ReflectionAndTransmissionAboveOne,
    /// An item of a baked scene ([`crate::BakedScene`]) is not what its
    /// checked constructor makes of its own numbers: hand-written or altered
    /// data, never what `tessera bake` writes.
    BadBaked {
        /// Its list.
        list: List,
        /// Its index in the list, from 0.
        index: u16,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::NotFinite(field) => write!(f, "{} is NaN or infinite", field.name()),
            Self::ZeroLength(field) => write!(f, "{} has zero length", field.name()),
            Self::NotPositive(field) => write!(f, "{} must be > 0", field.name()),
            Self::OutOfRange { field, range } => {
                write!(f, "{} must be in {}", field.name(), range)
            }
            Self::NearNotBeforeFar => {
                f.write_str("camera near distance must be smaller than the far distance")
            }
            Self::EmptyViewport => f.write_str("viewport must be at least 1x1 pixel"),
            Self::MaterialOutOfRange { id, count } => write!(
                f,
                "material {id} does not exist (the scene has {count} material(s))"
            ),
            Self::CapacityExceeded { list, capacity } => write!(
                f,
                "too many {}: the scene holds at most {capacity}",
                list.name()
            ),
            Self::DegenerateTriangle => f.write_str("triangle vertices are collinear (zero area)"),
            Self::MeshOutOfRange { id, count } => write!(
                f,
                "an instance of mesh {id}, which does not exist (the view has {count} mesh(es))"
            ),
            Self::BadMesh => f.write_str(
                "a mesh does not hold together (a vertex index out of range, normals not one \
                 unit vector per vertex, 65,536 faces or more, a BVH of other faces, \
                 meshes given twice, or instances of another view's meshes)",
            ),
            Self::BadBaked { list, index } => write!(
                f,
                "baked {} item {index} is not what its constructor makes of its numbers \
                 (bake the scene again)",
                list.name()
            ),
            Self::BvhMismatch => {
                f.write_str("the BVH was not built from this scene's triangles (build it again)")
            }
            Self::InvertedBox => f.write_str("box min corner must be <= max corner on every axis"),
            Self::DepthTooLarge { depth } => write!(
                f,
                "recursion depth {depth} is above the maximum {}",
                MAX_DEPTH
            ),
            Self::BadSampleCount => f.write_str(
                "sampler needs 1 to 4096 samples per pixel (stratified k: 1 to 64, \
                 adaptive k: 2 to 64)",
            ),
            Self::BadThreshold => f.write_str(
                "the adaptive and sparse samplers' threshold is a colour difference in \
                 8-bit units, an integer from 0 to 255 (adaptive:K,T or sparse:T)",
            ),
            Self::BadSpacing => f.write_str(
                "the sparse sampler's spacing is the distance between the rays of its first \
                 grid, 2 or 4 pixels (sparse:T,S)",
            ),
            Self::UnknownSampler => f.write_str(
                "unknown sampler: the samplers are corner, centre, prefiltered, offset:X,Y \
                 (each in [0, 1)), stratified:K (1-64), random:N (1-4096), \
                 adaptive:K (2-64) or adaptive:K,T (T: 0-255), and sparse, sparse:T \
                 (T: 0-255) or sparse:T,S (S: 2 or 4)",
            ),
            Self::TileOutOfFrame => f.write_str("tile coordinate is outside the frame"),
            Self::NotLinked => f.write_str(
                "the settings need a tile loop that is not linked (the Loops given leave out \
                 bounces, direct light, an encoding, or the adaptive or sparse sampler that \
                 they need)",
            ),
            Self::ReflectionAndTransmissionAboveOne => f.write_str(
                "material reflectivity + transparency must be <= 1 \
                 (it would send on more light than it receives)",
            ),
        }
    }
}

impl core::error::Error for Error {}

/// The largest coordinate magnitude and length a scene may use: `2^60` (about
/// `1.15e18`). Squared distances between points of such a scene stay below
/// `2^124`, inside the `f32` range with room for the renderer's sums, so the image
/// of a scene does not depend on its unit (see `docs/extremes.md`: a scene scaled
/// by `2^k` renders bit-identically as long as it validates).
pub const MAX_EXTENT: f32 = f32::from_bits((127 + 60) << 23);

/// The smallest sphere radius and camera near distance: `2^-52` (about `2.2e-16`).
/// Their squares, and the products of two scene lengths that the intersection tests
/// form, then stay normal `f32` numbers (above `2^-126`) with 22 binades to spare,
/// so that even the discriminant of a ray passing within `2^-20` of a sphere's
/// silhouette is normal: rounding stays relative (the image does not depend on the
/// scene's unit) and flushing denormals to zero changes nothing. Below, near-grazing
/// rays start to meet denormals (measured in `docs/extremes.md`).
pub const MIN_LENGTH: f32 = f32::from_bits((127 - 52) << 23);

/// The largest colour component a scene may use: `2^16` (65536), for material and
/// texture colours, light colours, the ambient light and the background (1 is full
/// scale). With the shader's cap on a light's `intensity / r^2` (`2^64`, in the
/// shading) no sum the renderer forms can overflow `f32`: a light's term is
/// at most about `2^16 * 2^64 * 2^17 = 2^97` (colour, irradiance, diffuse colour
/// plus highlight), summed over fewer than `2^14` lights, over the
/// `MAX_DEPTH + 1 <= 2^4` levels of a ray tree (whose weights sum to at most 1 per
/// level, reflectivity plus transparency being at most 1) and over at most `2^12`
/// samples of a pixel: below `2^128`. So an accepted scene (of fewer than 16,384
/// lights) never gives a NaN or infinite colour (`inf * 0` needs an infinity
/// first).
pub const MAX_COLOR: f32 = 65_536.0;

/// The deepest reflection/transmission recursion a frame may ask for.
pub const MAX_DEPTH: u8 = 8;

/// The range message for colours.
const COLOR_RANGE: &str = "[0, 65536] per component";

/// Checks that every component of `c` is finite and within `[0, MAX_COLOR]`.
pub(crate) fn color(c: crate::Color, field: Field) -> Result<crate::Color, Error> {
    if !c.is_finite() {
        return Err(Error::NotFinite(field));
    }
    let c = crate::Color::new(flush(c.r), flush(c.g), flush(c.b));
    if c.min_component() >= 0.0 && c.max_component() <= MAX_COLOR {
        Ok(c)
    } else {
        Err(Error::OutOfRange {
            field,
            range: COLOR_RANGE,
        })
    }
}

/// The range message for coordinates.
const EXTENT_RANGE: &str = "[-2^60, 2^60] (about 1.15e18) per component";
/// The range message for sizes.
const LENGTH_RANGE: &str = "[2^-52, 2^60] (about 2.2e-16 to 1.15e18)";

/// `x`, or a zero of its sign when it is subnormal (below `2^-126` in magnitude):
/// the one rule for subnormal numbers in a scene. Every number a scene takes
/// (positions, directions, lengths, scales, colours, intensities, weights) goes
/// through it where it is checked, and the host's loader and f64 reference apply
/// the same rule to the numbers of a scene file. A subnormal number carries fewer
/// bits than the others, and what `f32` and `f64` make of it differ (`1e-45` is
/// `1.4e-45` in `f32`, and a product with it underflows in `f32` only), so the
/// f32 core and the f64 reference would disagree: a camera at `z = 1e-45` above
/// its target rolled differently in each. Read as zero, it means the same to
/// both.
#[must_use]
pub(crate) const fn flush(x: f32) -> f32 {
    let bits = x.to_bits();
    if bits & 0x7f80_0000 == 0 {
        f32::from_bits(bits & 0x8000_0000)
    } else {
        x
    }
}

/// [`flush`] of each component.
#[must_use]
pub(crate) const fn flush3(v: crate::Vec3) -> crate::Vec3 {
    crate::Vec3::new(flush(v.x), flush(v.y), flush(v.z))
}

/// Checks that every component of `v` is finite and within [`MAX_EXTENT`].
pub(crate) fn position(v: crate::Vec3, field: Field) -> Result<crate::Vec3, Error> {
    let v = finite3(v, field)?;
    if v.abs().max_element() <= MAX_EXTENT {
        Ok(v)
    } else {
        Err(Error::OutOfRange {
            field,
            range: EXTENT_RANGE,
        })
    }
}

/// Checks that a size (already known finite and `> 0`) is within
/// `[MIN_LENGTH, MAX_EXTENT]`.
pub(crate) fn length(v: f32, field: Field) -> Result<f32, Error> {
    if (MIN_LENGTH..=MAX_EXTENT).contains(&v) {
        Ok(v)
    } else {
        Err(Error::OutOfRange {
            field,
            range: LENGTH_RANGE,
        })
    }
}

/// Checks that `v` is finite; [`flush`]ed.
pub(crate) fn finite(v: f32, field: Field) -> Result<f32, Error> {
    if v.is_finite() {
        Ok(flush(v))
    } else {
        Err(Error::NotFinite(field))
    }
}

/// Checks that every component of `v` is finite; [`flush3`]ed.
pub(crate) fn finite3(v: crate::Vec3, field: Field) -> Result<crate::Vec3, Error> {
    if v.is_finite() {
        Ok(flush3(v))
    } else {
        Err(Error::NotFinite(field))
    }
}

/// Checks that `v` is finite and within `[lo, hi]`.
pub(crate) fn in_range(
    v: f32,
    lo: f32,
    hi: f32,
    field: Field,
    range: &'static str,
) -> Result<f32, Error> {
    let v = finite(v, field)?;
    if v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(Error::OutOfRange { field, range })
    }
}

/// Checks that `v` is finite and normalises it (after [`flush3`]).
pub(crate) fn unit(v: crate::Vec3, field: Field) -> Result<crate::Vec3, Error> {
    finite3(v, field)?
        .try_normalize()
        .ok_or(Error::ZeroLength(field))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{
        Camera, Color, Sampler, Scene, Vec3, geometry::Aabb, geometry::Plane, geometry::Sphere,
        geometry::Triangle, light::Light, material::Material, sample::SubPixel, texture::Texture,
    };

    /// The smallest subnormal, and the largest, of each sign.
    const SUB: [f32; 4] = [1e-45, -1e-45, 1.1e-38, -1.1e-38];

    #[test]
    fn flush_keeps_normal_numbers_and_the_sign_of_zero() {
        for x in [
            0.0,
            1.0,
            -2.5,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::MAX,
            f32::INFINITY,
        ] {
            assert_eq!(flush(x).to_bits(), x.to_bits(), "{x}");
        }
        assert!(flush(f32::NAN).is_nan());
        for x in SUB {
            assert_eq!(flush(x).to_bits(), (0.0f32).copysign(x).to_bits(), "{x}");
        }
        assert_eq!(flush(-0.0).to_bits(), (-0.0f32).to_bits());
    }

    /// Every number a scene takes is read by the rule: a subnormal input gives
    /// what a zero of its sign gives, or the refusal of a zero.
    #[test]
    fn every_constructor_reads_subnormal_numbers_as_zero() {
        for s in SUB {
            let z = 0.0f32.copysign(s);
            let v = |a: f32| Vec3::new(0.5, a, -2.0);
            // Positions and directions.
            assert_eq!(Sphere::try_new(v(s), 1.0), Sphere::try_new(v(z), 1.0));
            assert_eq!(Plane::try_new(v(s), v(s)), Plane::try_new(v(z), v(z)));
            let tri = |a: f32| Triangle::try_new(v(a), Vec3::X, Vec3::Y);
            assert_eq!(tri(s), tri(z));
            assert_eq!(
                Aabb::try_new(v(s), Vec3::splat(3.0)),
                Aabb::try_new(v(z), Vec3::splat(3.0))
            );
            let cam = |a: f32| {
                Camera::try_new(
                    Vec3::new(0.0, 2.0, a),
                    Vec3::new(a, -1.0, a),
                    Vec3::new(a, 1.0, 0.0),
                    60.0,
                    0.1,
                    10.0,
                )
            };
            assert_eq!(cam(s), cam(z));
            // Colours, intensities, weights, texture numbers.
            let c = |a: f32| Color::new(0.5, a, 1.0);
            let light = |a: f32| Light::point(v(a), c(a), 2.0);
            assert_eq!(light(s), light(z));
            let dim = |a: f32| Light::point(Vec3::ZERO, Color::WHITE, a);
            assert_eq!(dim(s.abs()), dim(0.0));
            let material = |a: f32| {
                let checker = Texture::Checker {
                    a: c(a),
                    b: c(a),
                    scale: 2.0,
                };
                Material::matte(c(a)).with_texture(checker)
            };
            let add = |m: Material| {
                let mut scene = Scene::<crate::capacities!(materials: 1)>::new(cam(0.0).unwrap());
                scene
                    .add_material(m)
                    .map(|_| *scene.view().materials.first().unwrap())
            };
            assert_eq!(add(material(s).unwrap()), add(material(z).unwrap()));
            let reflective = |a: f32| Material::matte(Color::WHITE).with_reflectivity(a.abs());
            assert_eq!(add(reflective(s).unwrap()), add(reflective(0.0).unwrap()));
            let mut scene = Scene::<crate::capacities!()>::new(cam(0.0).unwrap());
            scene.set_ambient(c(s)).unwrap();
            scene.set_background(c(s)).unwrap();
            let view = scene.view();
            assert_eq!((view.ambient, view.background), (c(z), c(z)));
            assert_eq!(SubPixel::try_new(s.abs(), 0.5), SubPixel::try_new(0.0, 0.5));
            assert!(
                Sampler::Offset(SubPixel::try_new(s.abs(), 0.5).unwrap())
                    .validate()
                    .is_ok()
            );
            // Lengths and scales: read as zero, refused as zero is.
            let zero = Err(Error::NotPositive(Field::SphereRadius));
            assert_eq!(Sphere::try_new(Vec3::ZERO, s.abs()), zero);
            let checker = Texture::Checker {
                a: Color::WHITE,
                b: Color::BLACK,
                scale: s.abs(),
            };
            assert_eq!(
                checker.validate(),
                Err(Error::NotPositive(Field::TextureScale))
            );
            let fringes = Texture::Fringes {
                color: Color::WHITE,
                spacing: s.abs(),
            };
            assert_eq!(
                fringes.validate(),
                Err(Error::NotPositive(Field::FringeSpacing))
            );
            assert_eq!(
                Camera::try_new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 60.0, s.abs(), 1.0),
                Err(Error::NotPositive(Field::Near))
            );
        }
    }
}
