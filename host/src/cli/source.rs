//! The scene a command renders: a built-in or a scene file.

use super::{Common, Error};
use std::path::{Path, PathBuf};
use tessera_core::builtin::Builtin;
use tessera_core::{Camera, RenderSettings, SceneView, Viewport};
use tessera_host::desc::{DescError, SceneDesc};
use tessera_host::output::{Input, Target};

/// A scene to render: a built-in (rendered from the core's own code) or a file.
pub enum Source {
    Builtin(Builtin),
    File(String, Box<SceneDesc>),
}

impl Source {
    /// The scene named on the command line (`None`: the default built-in), and
    /// a glTF file's camera by name. A file's warnings (accepted values that
    /// look like mistakes, what a glTF file has that is not read) go to stderr.
    pub fn open(name: Option<&str>, camera: Option<&str>) -> Result<Self, Error> {
        let gltf = name.is_some_and(|n| tessera_host::file::is_gltf(Path::new(n)));
        if let (Some(c), false) = (camera, gltf) {
            return Err(Error::CameraOfNoGltf(c.to_string()));
        }
        let Some(name) = name else {
            return Ok(Self::Builtin(Builtin::DEFAULT));
        };
        if let Some(b) = Builtin::from_name(name) {
            return Ok(Self::Builtin(b));
        }
        let path = Path::new(name);
        if !path.exists() && !name.ends_with(".toml") && !gltf {
            return Err(Error::NoSuchScene(name.to_string()));
        }
        let desc = if gltf {
            tessera_host::file::load_gltf(path, camera)?
        } else {
            tessera_host::file::load(path)?
        };
        for w in tessera_host::file::warnings(&desc) {
            eprintln!(
                "tessera: warning: {}",
                tessera_host::escape(&format!("{name}: {w}"))
            );
        }
        Ok(Self::File(name.to_string(), Box::new(desc)))
    }

    /// The files the scene was read from, which no output may replace: the scene
    /// file, the files of its meshes (OBJ, glTF) and its image textures' files
    /// (relative to the scene file's folder, as [`tessera_host::file::load`]
    /// reads them).
    fn inputs(&self) -> Vec<Input> {
        let Self::File(name, desc) = self else {
            return Vec::new();
        };
        let scene = Path::new(name);
        let base = scene.parent().unwrap_or(Path::new(""));
        let meshes = desc.meshes.iter().enumerate().filter_map(|(i, m)| {
            let path = tessera_host::mesh::obj_file(m, base)?;
            let what = format!(
                "the OBJ file {} of mesh {} (scene {name})",
                path.display(),
                i + 1
            );
            Some(Input { path, what })
        });
        let images = desc.materials.iter().filter_map(|m| match &m.texture {
            Some(tessera_host::desc::TextureDesc::Image { file, .. }) => Some(Input {
                path: base.join(file),
                what: format!(
                    "the image file {file} of material {:?} (scene {name})",
                    m.name
                ),
            }),
            _ => None,
        });
        std::iter::once(Input::scene(scene))
            .chain(meshes)
            .chain(images)
            .collect()
    }

    /// Checks an output path against the inputs (see [`Target::check`]).
    pub fn target(&self, path: &Path) -> Result<Target, Error> {
        Ok(Target::check(path, &self.inputs())?)
    }

    /// Checks several outputs against the inputs, written all or nothing (see
    /// [`Target::check_all`]).
    pub fn targets(&self, paths: &[PathBuf]) -> Result<Vec<Target>, Error> {
        Ok(Target::check_all(paths, &self.inputs())?)
    }

    pub fn name(&self) -> &str {
        match self {
            Self::Builtin(b) => b.name(),
            Self::File(n, _) => n,
        }
    }

    /// An error about this scene's description.
    pub fn error(&self, source: DescError) -> Error {
        Error::Scene {
            name: self.name().to_string(),
            source,
        }
    }

    /// The scene at frame `n` of its animation (a scene file's
    /// `[[keyframes]]`).
    pub fn at_frame(self, n: u32) -> Result<Self, Error> {
        let d = match &self {
            Self::File(_, d) if !d.keyframes.is_empty() => d,
            _ => {
                return Err(self.error(DescError {
                    item: "--frame".into(),
                    message: "the scene has no animation (no [[keyframes]]): \
                              only a scene file's keyframes move it"
                        .into(),
                }));
            }
        };
        let at = d.at_frame(n).map_err(|e| self.error(e))?;
        match self {
            Self::File(name, _) => Ok(Self::File(name, Box::new(at))),
            other => Ok(other),
        }
    }

    /// The scene description (for the reference).
    pub fn desc(&self) -> SceneDesc {
        match self {
            Self::Builtin(b) => tessera_host::file::builtin_desc(*b),
            Self::File(_, d) => (**d).clone(),
        }
    }

    /// Settings, viewport and tile size: the scene's own, after the command-line
    /// overrides.
    pub fn settings(&self, c: &Common) -> Result<(RenderSettings, Viewport, usize), Error> {
        let (mut s, mut vp, mut tile) = match self {
            Self::Builtin(b) => (b.settings(), Viewport::new(320, 240), 16),
            Self::File(_, d) => (
                d.settings().map_err(|e| self.error(e))?,
                d.viewport(),
                d.render.tile,
            ),
        };
        s.sampler = c.sampler.unwrap_or(s.sampler);
        s.max_depth = c.depth.unwrap_or(s.max_depth);
        s.seed = c.seed.unwrap_or(s.seed);
        s.encoding = c.encoding.unwrap_or(s.encoding);
        if let Some((w, h)) = c.size {
            vp = Viewport::new(w, h);
        }
        tile = c.tile.unwrap_or(tile);
        s.validate()?;
        Ok((s, vp, tile))
    }

    /// Runs `f` with the core scene's view and camera.
    pub fn with_core<R>(
        &self,
        f: impl FnOnce(&SceneView<'_>, &Camera) -> Result<R, Error>,
    ) -> Result<R, Error> {
        match self {
            Self::Builtin(b) => b.with_scene(f)?,
            Self::File(_, d) => {
                let s = d.to_core().map_err(|e| self.error(e))?;
                s.with_view(|view| f(view, s.camera()))
            }
        }
    }
}
