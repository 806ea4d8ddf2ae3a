//! The one table of plugins: every plugin name ophis knows, by the element it appears as.
//! Adding a plugin is one new file (manual, declaration, loader, model) and one line here.

use super::suggest::did_you_mean;
use super::{Args, Info, Node, Plugin, SceneError, Tag, Warning};
use crate::bsdf::{self, Material};
use crate::camera::{self, Sensor};
use crate::film::{self, FilmSettings, Filter};
use crate::integrator;
use crate::light::{self, Light};
use crate::math::Transform;
use crate::plugin::SpectrumKind;
use crate::sampler;
use crate::scene::{IntegratorSettings, SamplerSettings};
use crate::shape::{self, Parts};
use crate::texture::{self, FloatTexture, SpectrumTexture, Texture, Want};

/// The plugins one element can name, with the request `C` their loaders take, and what
/// becomes of the Mitsuba plugins of that element that ophis does not have: a scene using one
/// still loads, with a warning, either without it or with `instead` read in its place (any
/// other unknown name is an error with a suggestion).
pub(crate) struct Kind<T: 'static, C: 'static = ()> {
    tag: Tag,
    plugins: &'static [&'static Plugin<T, C>],
    mitsuba_only: &'static [&'static str],
    instead: Option<&'static Plugin<T, C>>,
}

/// BSDFs.
pub(crate) const BSDFS: Kind<Material> = Kind {
    tag: Tag::Bsdf,
    plugins: &[
        &bsdf::absorption::PLUGIN,
        &bsdf::bumpmap::PLUGIN,
        &bsdf::conductor::PLUGIN,
        &bsdf::dielectric::PLUGIN,
        &bsdf::diffuse::PLUGIN,
        &bsdf::filmstack::PLUGIN,
        &bsdf::layered::PLUGIN,
        &bsdf::normalmap::PLUGIN,
        &bsdf::null::PLUGIN,
        &bsdf::plastic::PLUGIN,
        &bsdf::roughconductor::PLUGIN,
        &bsdf::roughdielectric::PLUGIN,
        &bsdf::roughplastic::PLUGIN,
        &bsdf::roughthinfilm::PLUGIN,
        &bsdf::roughthinfilm::THESIS_PLUGIN,
        &bsdf::roughthinfilmconductor::PLUGIN,
        &bsdf::thindielectric::PLUGIN,
        &bsdf::thinfilm::PLUGIN,
        &bsdf::thinfilm::THESIS_PLUGIN,
        &bsdf::thinfilmconductor::PLUGIN,
        &bsdf::thinfilmconductor::THESIS_PLUGIN,
        &bsdf::twosided::PLUGIN,
    ],
    mitsuba_only: &[],
    instead: None,
};

/// Textures.
pub(crate) const TEXTURES: Kind<Texture, Want> = Kind {
    tag: Tag::Texture,
    plugins: &[
        &texture::bitmap::PLUGIN,
        &texture::checkerboard::PLUGIN,
        &texture::per_scale::PLUGIN,
        &texture::scales::PLUGIN,
    ],
    mitsuba_only: &[],
    instead: None,
};

/// Emitters; the request is the index of the shape an emitter is nested in.
pub(crate) const EMITTERS: Kind<Vec<Light>, Option<u32>> = Kind {
    tag: Tag::Emitter,
    plugins: &[
        &light::area::PLUGIN,
        &light::constant::PLUGIN,
        &light::directional::PLUGIN,
        &light::envmap::PLUGIN,
        &light::point::PLUGIN,
        &light::sunsky::PLUGIN,
        &light::sunsky::SKY_PLUGIN,
        &light::sunsky::SUN_PLUGIN,
    ],
    mitsuba_only: &["spot", "projector", "mesh_attribute", "volumelight"],
    instead: None,
};

/// Shapes; the request is the transform of the `instance` placing them (identity otherwise).
/// `shapegroup` and `instance` are structure, handled by the scene builder.
pub(crate) const SHAPES: Kind<Parts, Transform> = Kind {
    tag: Tag::Shape,
    plugins: &[
        &shape::cube::PLUGIN,
        &shape::cylinder::PLUGIN,
        &shape::disk::PLUGIN,
        &shape::litter::PLUGIN,
        &shape::obj::PLUGIN,
        &shape::ply::PLUGIN,
        &shape::rectangle::PLUGIN,
        &shape::serialized::PLUGIN,
        &shape::snake::PLUGIN,
        &shape::sphere::PLUGIN,
        &shape::torus::PLUGIN,
    ],
    mitsuba_only: &[
        "bsplinecurve",
        "linearcurve",
        "sdfgrid",
        "ellipsoids",
        "ellipsoidsmesh",
    ],
    instead: None,
};

/// Sensors; the request is the image size given on the command line, which overrides the
/// film's. Mitsuba's other sensors (3.x and 0.6) render as a pinhole camera.
pub(crate) const SENSORS: Kind<Sensor, Option<(u32, u32)>> = Kind {
    tag: Tag::Sensor,
    plugins: &[
        &camera::orthographic::PLUGIN,
        &camera::perspective::PLUGIN,
        &camera::thinlens::PLUGIN,
    ],
    mitsuba_only: &[
        "radiancemeter",
        "irradiancemeter",
        "distant",
        "batch",
        "spherical",
        "telecentric",
        "fluencemeter",
        "perspective_rdist",
    ],
    instead: Some(&camera::perspective::PLUGIN),
};

/// Films.
pub(crate) const FILMS: Kind<FilmSettings> = Kind {
    tag: Tag::Film,
    plugins: &[&film::PLUGIN],
    mitsuba_only: &["specfilm", "mfilm", "tiledhdrfilm"],
    instead: Some(&film::PLUGIN),
};

/// Reconstruction filters (nested in a film).
pub(crate) const RFILTERS: Kind<Filter> = Kind {
    tag: Tag::Rfilter,
    plugins: &[
        &film::box_filter::PLUGIN,
        &film::gaussian::PLUGIN,
        &film::tent::PLUGIN,
    ],
    mitsuba_only: &["lanczos", "mitchell", "catmullrom"],
    instead: Some(&film::gaussian::PLUGIN),
};

/// Samplers (nested in a sensor).
pub(crate) const SAMPLERS: Kind<SamplerSettings> = Kind {
    tag: Tag::Sampler,
    plugins: &[&sampler::independent::PLUGIN, &sampler::sobol::PLUGIN],
    mitsuba_only: &[],
    instead: None,
};

/// Integrators. Mitsuba's others (3.x and 0.6) render as `path`, reading its parameters.
pub(crate) const INTEGRATORS: Kind<IntegratorSettings> = Kind {
    tag: Tag::Integrator,
    plugins: &[
        &integrator::aov::PLUGIN,
        &integrator::direct::PLUGIN,
        &integrator::moment::PLUGIN,
        &integrator::path::PLUGIN,
    ],
    mitsuba_only: &[
        "volpath",
        "volpathmis",
        "prb",
        "prb_basic",
        "prbvolpath",
        "prb_projective",
        "direct_projective",
        "ptracer",
        "stokes",
        "depth",
        "volpath_simple",
        "bdpt",
        "pssmlt",
        "mlt",
        "erpt",
        "photonmapper",
        "ppm",
        "sppm",
        "vpl",
        "ao",
        "adaptive",
        "irrcache",
        "multichannel",
        "field",
    ],
    instead: Some(&integrator::path::PLUGIN),
};

impl<T, C> Kind<T, C> {
    fn infos(&self) -> impl Iterator<Item = &'static Info> {
        self.plugins.iter().map(|p| &p.info)
    }

    /// "unknown bsdf 'roughconductr' (did you mean 'roughconductor'?)", at the element.
    fn unknown(&self, node: &Node) -> SceneError {
        let names = self
            .infos()
            .flat_map(|i| std::iter::once(i.name).chain(i.aliases.iter().copied()));
        let hint = did_you_mean(&node.plugin, names);
        SceneError::at(
            &node.loc,
            format!(
                "unknown {} plugin '{}'{hint}; `ophis plugins` lists the known ones",
                self.tag, node.plugin
            ),
        )
    }

    /// Builds what `node` describes; `None` for a Mitsuba plugin ophis does not have and puts
    /// nothing in place of (warned about).
    fn load(
        &self,
        node: &Node,
        request: C,
        warnings: &mut Vec<Warning>,
    ) -> Result<Option<T>, SceneError> {
        let plugin = match self.plugins.iter().find(|p| p.info.is_called(&node.plugin)) {
            Some(p) => p,
            None if self.mitsuba_only.contains(&node.plugin.as_str()) => {
                let what = match self.instead {
                    Some(p) => format!("it is read as '{}'", p.info.name),
                    None => "it is ignored".into(),
                };
                warnings.push(Warning {
                    loc: node.loc.clone(),
                    message: format!(
                        "{} '{}' is a Mitsuba plugin ophis does not have; {what}",
                        self.tag, node.plugin
                    ),
                });
                match self.instead {
                    Some(p) => p,
                    None => return Ok(None),
                }
            }
            None => return Err(self.unknown(node)),
        };
        (plugin.load)(&mut Args::new(node, &plugin.info, warnings), request).map(Some)
    }

    /// [`Kind::load`] for a kind that always puts something in place of what it lacks.
    fn load_one(
        &self,
        node: &Node,
        request: C,
        warnings: &mut Vec<Warning>,
    ) -> Result<T, SceneError> {
        self.load(node, request, warnings)?.ok_or_else(|| {
            SceneError::at(&node.loc, format!("{} is not supported", node.describe()))
        })
    }
}

/// Every plugin's description, grouped by element, sorted by name within a group.
pub fn all() -> Vec<&'static Info> {
    let mut v: Vec<&'static Info> = BSDFS.infos().collect();
    v.extend(TEXTURES.infos());
    v.extend(EMITTERS.infos());
    v.extend(SHAPES.infos());
    v.extend(SENSORS.infos());
    v.extend(FILMS.infos());
    v.extend(RFILTERS.infos());
    v.extend(SAMPLERS.infos());
    v.extend(INTEGRATORS.infos());
    v.sort_by_key(|i| (i.tag.as_str(), i.name.to_lowercase()));
    v
}

/// The plugin called `name` (or an alias) that appears as `tag`.
pub fn info(tag: Tag, name: &str) -> Option<&'static Info> {
    all()
        .into_iter()
        .find(|i| i.tag == tag && i.is_called(name))
}

/// The plugin called `name` among any kind (for `ophis plugins NAME`).
pub fn find(name: &str) -> Vec<&'static Info> {
    all().into_iter().filter(|i| i.is_called(name)).collect()
}

/// Builds the BSDF a `<bsdf>` node describes (nested BSDFs and textures included).
pub fn bsdf(node: &Node, warnings: &mut Vec<Warning>) -> Result<Material, SceneError> {
    BSDFS.load_one(node, (), warnings)
}

/// Builds the lights an `<emitter>` describes (`sunsky` is two; a Mitsuba plugin ophis lacks
/// is none, with a warning); `shape` is the index of the shape it is nested in.
pub fn emitter(
    node: &Node,
    shape: Option<u32>,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<Light>, SceneError> {
    Ok(EMITTERS.load(node, shape, warnings)?.unwrap_or_default())
}

/// Builds the shapes a `<shape>` describes (a `snake` is one per part; a Mitsuba shape ophis
/// lacks, or a mesh of only zero-area triangles, is none, with a warning), placed after
/// `parent`.
pub fn shape(
    node: &Node,
    parent: Transform,
    warnings: &mut Vec<Warning>,
) -> Result<Parts, SceneError> {
    Ok(SHAPES.load(node, parent, warnings)?.unwrap_or_default())
}

/// Builds a texture of the kind asked for.
pub fn texture(
    node: &Node,
    want: Want,
    warnings: &mut Vec<Warning>,
) -> Result<Texture, SceneError> {
    TEXTURES.load_one(node, want, warnings)
}

/// Builds the camera, film and sampler a `<sensor>` describes; `resolution`, when given,
/// replaces the film's size.
pub fn sensor(
    node: &Node,
    resolution: Option<(u32, u32)>,
    warnings: &mut Vec<Warning>,
) -> Result<Sensor, SceneError> {
    SENSORS.load_one(node, resolution, warnings)
}

/// Reads a `<film>` (nested in a sensor).
pub fn film(node: &Node, warnings: &mut Vec<Warning>) -> Result<FilmSettings, SceneError> {
    FILMS.load_one(node, (), warnings)
}

/// Builds an `<rfilter>` (nested in a film).
pub fn rfilter(node: &Node, warnings: &mut Vec<Warning>) -> Result<Filter, SceneError> {
    RFILTERS.load_one(node, (), warnings)
}

/// Reads a `<sampler>` (nested in a sensor).
pub fn sampler(node: &Node, warnings: &mut Vec<Warning>) -> Result<SamplerSettings, SceneError> {
    SAMPLERS.load_one(node, (), warnings)
}

/// Reads an `<integrator>` (and the integrators nested in it).
pub fn integrator(
    node: &Node,
    warnings: &mut Vec<Warning>,
) -> Result<IntegratorSettings, SceneError> {
    INTEGRATORS.load_one(node, (), warnings)
}

/// A texture used as a colour.
pub(crate) fn spectrum_texture(
    node: &Node,
    kind: SpectrumKind,
    warnings: &mut Vec<Warning>,
) -> Result<SpectrumTexture, SceneError> {
    match texture(node, Want::Spectrum(kind), warnings)? {
        Texture::Spectrum(t) => Ok(t),
        _ => Err(SceneError::at(
            &node.loc,
            format!("{} cannot be used as a colour", node.describe()),
        )),
    }
}

/// A texture used as a number.
pub(crate) fn float_texture(
    node: &Node,
    warnings: &mut Vec<Warning>,
) -> Result<FloatTexture, SceneError> {
    match texture(node, Want::Float, warnings)? {
        Texture::Float(t) => Ok(t),
        _ => Err(SceneError::at(
            &node.loc,
            format!("{} cannot be used as a number", node.describe()),
        )),
    }
}
