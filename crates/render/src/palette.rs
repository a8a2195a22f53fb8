//! Colour quantization: linear RGB → sRGB → the terminal's [`ColorDepth`].
//!
//! The renderer works in linear RGB; colours are sRGB-encoded here, once, when quantized (colours from
//! files that are meant as display colours should go through [`srgb_to_linear`]
//! first). The palettes are xterm's defaults.
//!
//! The picture in 256 and 16 colours is drawn from light ramps ([`LightRamp`], issue #33): every
//! sample of one chromaticity (a surface lit by white light and fogged toward black keeps its own)
//! takes the entry of that chromaticity's ramp at its intensity, entries chosen in OKLab for hue as
//! well as lightness, in order of lightness, each holding one run: calm bands of the surface's own
//! hue, no pattern. [`picture_color`] is that at any depth. [`quantize`] is plain nearest colour by
//! squared distance in sRGB 0..255: truecolor, and the overlays' colours.

use std::sync::OnceLock;

use glam::Vec3;
use wide::f32x8;

use super::pipeline::{CEILING_SRGB, FLOOR_SRGB};
use super::shade::{Srgb8Tables, srgb_to_linear};
use mazewalk_term::frame::{Color, ColorDepth};

pub use mazewalk_term::frame::xterm_rgb;
pub(crate) use mazewalk_term::frame::{ANSI16, CUBE_LEVELS};

/// A linear colour as sRGB bytes (clamped to 0..1 first; NaN → 0).
#[must_use]
#[inline]
pub(crate) fn to_srgb8(linear: Vec3) -> [u8; 3] {
    Srgb8Tables::get().encode3(linear)
}

fn distance2(a: [u8; 3], b: [u8; 3]) -> u32 {
    (0..3).map(|k| u32::from(a[k].abs_diff(b[k])).pow(2)).sum()
}

/// The nearest xterm-256 index in 16–231 (cube) or 232–255 (greys) to an sRGB colour.
#[must_use]
pub(crate) fn xterm256(rgb: [u8; 3]) -> u8 {
    // Both candidates come from small tables of `cube_level` and `grey_index` (built on first use), as
    // this runs twice per cell in 256 colours.
    static TABLES: OnceLock<([u8; 256], [u8; 766])> = OnceLock::new();
    let (level, grey) = TABLES.get_or_init(|| {
        (std::array::from_fn(|v| cube_level(v as u8)), std::array::from_fn(|sum| grey_index(sum as u32)))
    });
    let [r, g, b] = rgb.map(|v| level[usize::from(v)]);
    let cube = 16 + 36 * r + 6 * g + b;
    let grey = grey[usize::from(rgb[0]) + usize::from(rgb[1]) + usize::from(rgb[2])];
    if distance2(xterm_rgb(grey), rgb) < distance2(xterm_rgb(cube), rgb) { grey } else { cube }
}

/// The index (0–5) of the cube level nearest to `v` (the lower one on a tie).
fn cube_level(v: u8) -> u8 {
    (0..6).min_by_key(|&k| CUBE_LEVELS[usize::from(k)].abs_diff(v)).unwrap_or(0)
}

/// The grey ramp entry (232–255) nearest to the mean of three channels summing to `sum`.
fn grey_index(sum: u32) -> u8 {
    let mean = sum as f32 / 3.0;
    232 + ((mean - 8.0) / 10.0).round().clamp(0.0, 23.0) as u8
}

/// The nearest of the 16 ANSI colours to an sRGB colour.
#[must_use]
pub fn ansi16(rgb: [u8; 3]) -> u8 {
    (0..16u8).min_by_key(|&i| distance2(ANSI16[usize::from(i)], rgb)).unwrap_or(0)
}

/// A linear colour quantized to `depth` (no dithering; [`ColorDepth::None`] gives [`Color::Default`]).
#[must_use]
pub(crate) fn quantize(linear: Vec3, depth: ColorDepth) -> Color {
    quantize_srgb8(to_srgb8(linear), depth)
}

/// An sRGB colour quantized to `depth` (no dithering; [`ColorDepth::None`] gives [`Color::Default`]).
#[must_use]
#[inline] // truecolor, every cell of the block charsets: a wrapping, not a call
pub fn quantize_srgb8(rgb: [u8; 3], depth: ColorDepth) -> Color {
    match depth {
        ColorDepth::None => Color::Default,
        ColorDepth::Ansi16 => Color::Indexed(ansi16(rgb)),
        ColorDepth::Ansi256 => Color::Indexed(xterm256(rgb)),
        ColorDepth::TrueColor => Color::Rgb(rgb[0], rgb[1], rgb[2]),
    }
}

/// The palette's 256 entries in OKLab.
struct Entries {
    oklab: [Vec3; 256],
}

/// [`Entries`], built on first use (768 `powf` and cube roots: a few µs).
fn entries() -> &'static Entries {
    static ENTRIES: OnceLock<Entries> = OnceLock::new();
    ENTRIES.get_or_init(|| Entries {
        oklab: std::array::from_fn(|i| {
            oklab(Vec3::from_array(xterm_rgb(i as u8).map(|v| srgb_to_linear(f32::from(v) / 255.0))))
        }),
    })
}

/// OKLab of a linear sRGB colour (Björn Ottosson, <https://bottosson.github.io/posts/oklab/>): L in 0..1,
/// Euclidean distance ≈ perceived difference.
#[must_use]
pub(crate) fn oklab(linear: Vec3) -> Vec3 {
    Vec3::from_array(mazewalk_term::frame::oklab(linear.to_array(), |v| v.max(0.0).cbrt()))
}

/// How a light ramp chooses its entries: the weights of [`cost`] and of a ramp's steps.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Weights {
    /// A hue shift (ΔH: the chord between the two hues at their chromas), per unit squared.
    hue: f32,
    /// A chroma difference, per unit squared.
    chroma: f32,
    /// The factor on [`Weights::chroma`] where the entry is more saturated than the target: a wall
    /// shown more vivid than it is hides the fade into the dark (issue #39), a greyer one does not.
    over: f32,
    /// A grey entry shown for a coloured target, per unit squared of the target's chroma above
    /// [`Weights::muted`].
    grey: f32,
    /// A target with no more chroma than this may be shown grey at no cost beyond its distance: a
    /// muted colour the palette has no entry near shows as its grey, not as a more vivid or another
    /// hue (issue #39: the exit's glow rimmed in olive, a tan wall's dark edge orange).
    muted: f32,
    /// For a chromaticity of the exit's green ([`exit_green`]) with no more chroma than the first of
    /// these times its lightness (OKLab C ⁄ L), [`Weights::muted`] is the second: a grey wall in the
    /// exit's light, tinted toward its green (`shade::exit_lit_wall`), has 0.06 at the first look
    /// (chroma 0.037–0.039 at L 0.62–0.65), and the cube's nearest greens there, (95, 135, 95) and
    /// (135, 175, 135), are 0.06–0.07 darker or lighter and twice as saturated: 0.07–0.08 off, where
    /// its grey is 0.04 off (issue #39: the built-in maze nose to such a wall, mean error 0.070).
    /// A grey costs only its distance a little higher up (to 0.035, not 0.03); beyond, where the
    /// hue error counts a sample (0.04), such a wall keeps its greens.
    muted_glow: (f32, f32),
    /// A hue turned by more than [`Weights::turn_free`] (radians), per radian squared beyond it
    /// times the target's chroma squared: on top of ΔH, which shrinks with the chroma, so a pale
    /// grey-green may not take a yellow entry ([`cost`]).
    turn: f32,
    /// See [`Weights::turn`].
    turn_free: f32,
    /// For a target of chroma below [`Weights::vivid_below`], an entry more than
    /// [`Weights::vivid_from`] times as saturated, per unit of chroma beyond, squared, on top of
    /// [`Weights::over`]: the cube's nearest entries of a dark muted colour's own hue are vivid ones
    /// (a tan wall's dark edge: the cube's orange, 2.75× its chroma), and its grey is nearer. (A
    /// dark saturated wall keeps its dark vivid entry: a dark green's other choice is a lighter
    /// one, and a wall far off would not darken.)
    vivid: f32,
    /// See [`Weights::vivid`].
    vivid_from: f32,
    /// See [`Weights::vivid`].
    vivid_below: f32,
    /// A step between two coloured entries of a ramp, per unit of their chroma difference squared.
    step: f32,
}

/// The cost of showing OKLab colour `target` (of chroma `target_chroma` and hue angle
/// `target_hue`) as `entry`: lightness and hue as a viewer weighs them. A hue shift costs
/// [`Weights::hue`] times a lightness step as large, and a turn of the hue angle beyond
/// [`Weights::turn_free`] costs [`Weights::turn`] more (ΔH alone lets a pale colour take an entry
/// of another hue: its chord is short where the chroma is small, but the eye still reads olive
/// against grey-green). A grey entry loses the hue altogether, which costs [`Weights::grey`] times
/// the target's chroma above [`Weights::muted`] squared on top: a blue wall may come out a little
/// more or less blue, lighter or darker, but not grey or violet; a muted one may come out grey, and
/// does rather than as a far more saturated entry ([`Weights::vivid`]).
fn cost(target: Vec3, target_chroma: f32, target_hue: f32, entry: &RampEntry, w: &Weights) -> f32 {
    let dl = entry.lab.x - target.x;
    let (da, db) = (entry.lab.y - target.y, entry.lab.z - target.z);
    let dc = entry.chroma - target_chroma;
    let dh2 = (da * da + db * db - dc * dc).max(0.0);
    let (grey, turn, vivid) = if entry.chroma < GREY_ENTRY {
        let above = (target_chroma - w.muted).max(0.0);
        (w.grey * above * above, 0.0, 0.0)
    } else {
        // Both angles are atan2's, in −π..=π: their difference needs no remainder (a library call).
        let turned = (entry.hue - target_hue).abs();
        let beyond = (turned.min(std::f32::consts::TAU - turned) - w.turn_free).max(0.0);
        let vivid = if target_chroma < w.vivid_below {
            (entry.chroma - w.vivid_from * target_chroma).max(0.0)
        } else {
            0.0
        };
        (0.0, w.turn * beyond * beyond * target_chroma * target_chroma, w.vivid * vivid * vivid)
    };
    let chroma = if dc > 0.0 { w.chroma * w.over } else { w.chroma };
    dl * dl + chroma * dc * dc + w.hue * dh2 + grey + turn + vivid
}

/// [`Weights::muted_glow`] in 256 colours. The faintest glow on a grey wall (C ⁄ L 0.06; its ramps'
/// chromaticities, on a grid, up to about 0.065) is below 0.07; the next look (0.09) above, as are a
/// course file's sage walls of that hue (the CS559 10×10 maze's (99, 127, 108): 0.076).
const MUTED_GLOW: (f32, f32) = (0.07, 0.035);
/// An entry with less chroma than this is grey (the cube's and the ramp's greys have none).
const GREY_ENTRY: f32 = 0.015;
/// A chromaticity whose brightest colour has less chroma than this is grey: its ramp holds greys only.
const COLOURED: f32 = 0.045;

/// The difference of two hue angles (radians), in 0..=π.
#[must_use]
pub(crate) fn hue_difference(a: f32, b: f32) -> f32 {
    let d = (a - b).abs() % std::f32::consts::TAU;
    d.min(std::f32::consts::TAU - d)
}

/// Which palette a light ramp is built from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Palette {
    /// The 16 ANSI colours (xterm's defaults; terminals differ, see [`Palette::of`]).
    Ansi16,
    /// Indices 16–255 of xterm's 256 colours (the cube and the greys, the same on every terminal).
    Xterm256,
}

impl Palette {
    /// The palette of a colour depth: `None` for truecolor and no colour.
    ///
    /// The 16 colours' real values depend on the terminal's theme; their ramps are measured on xterm's
    /// defaults, but are made of what holds in nearly every theme: black, the two greys and white in
    /// that order of lightness, and each hue's normal and bright colour, the bright one lighter.
    #[must_use]
    pub fn of(depth: ColorDepth) -> Option<Palette> {
        match depth {
            ColorDepth::Ansi16 => Some(Palette::Ansi16),
            ColorDepth::Ansi256 => Some(Palette::Xterm256),
            ColorDepth::None | ColorDepth::TrueColor => None,
        }
    }

    /// The palette's entries.
    fn indices(self) -> std::ops::RangeInclusive<u8> {
        match self {
            Palette::Ansi16 => 0..=15,
            Palette::Xterm256 => 16..=255,
        }
    }

    /// How its ramps weigh hue, chroma, greys and steps ([`cost`], [`LightRamp::of_surface`]), chosen on
    /// the measures of issues #33 and #39 over held-out views (`benches/examples/picture.rs`). In 256
    /// colours the cube is coarse for muted colours (a tan wall's nearest entry is a grey 0.05 away
    /// in OKLab, its nearest of its hue twice as saturated): hue weighs eight times as much as
    /// lightness (ΔH²: 8), and an entry more saturated than the wall costs three times a greyer one,
    /// so muted walls are not painted vivid (issue #39: the median chromatic sample was 3.3×
    /// truecolor's), and its bands keep their saturation (steps: 2). A grey costs only its distance
    /// for a target of chroma up to 0.03 (the measures count hue from 0.04) and dearly above (100 per
    /// unit of chroma beyond, squared), so a wall keeps its hue but the darkest, palest shades of a
    /// muted colour take the grey they are nearest; a hue turned more than 25° costs 1000 per radian
    /// beyond, squared, times the chroma squared, and for a target of chroma below 0.06 an entry
    /// more than 1.7× as saturated 20 per unit beyond, squared, so those shades take neither a
    /// neighbouring hue nor a vivid entry of their own (issue #39: the exit's glow on the grey floor stepped grey → olive → grey-green, a
    /// tan wall's dark edge was orange). In 16 colours there are six hues: hue weighs 4, greys 8
    /// from any chroma, no turn, or every wall between two hues would be grey.
    fn weights(self) -> Weights {
        match self {
            Palette::Xterm256 => Weights {
                hue: 8.0,
                chroma: 1.0,
                over: 3.0,
                grey: 100.0,
                muted: 0.03,
                muted_glow: MUTED_GLOW,
                turn: 1000.0,
                turn_free: 25f32.to_radians(),
                vivid: 20.0,
                vivid_from: 1.7,
                vivid_below: 0.06,
                step: 2.0,
            },
            Palette::Ansi16 => Weights {
                hue: 4.0,
                chroma: 1.0,
                over: 1.0,
                grey: 8.0,
                muted: 0.0,
                muted_glow: (0.0, 0.0),
                turn: 0.0,
                turn_free: 0.0,
                vivid: 0.0,
                vivid_from: 1.0,
                vivid_below: 0.0,
                step: 4.0,
            },
        }
    }

    /// A ramp holds greys and the entries whose hue is within this of its chromaticity's (radians):
    /// 40° in 256 colours (the pale entries of a hue are few); 45° in 16, whose six hues are 60°
    /// apart (an orange wall is red there).
    #[must_use]
    pub(crate) fn hue_span(self) -> f32 {
        match self {
            Palette::Xterm256 => 40f32.to_radians(),
            Palette::Ansi16 => 45f32.to_radians(),
        }
    }

    /// The OKLab colour a ramp of this palette aims at for a sample of OKLab colour `lab`: itself in
    /// 256 colours. In 16 colours, whose greys are black, L 0.6, 0.92 and white, the lightness of a
    /// maze scene (walls up to about 0.65 near, the ceiling about 0.25) is stretched over the
    /// palette's, so the floor, the ceiling and the walls, near and far, fall on different entries.
    fn target(self, lab: Vec3, stretch: (f32, f32)) -> Vec3 {
        match self {
            Palette::Xterm256 => lab,
            Palette::Ansi16 => {
                let (low, high) = stretch;
                let l = ((lab.x - low) / (high - low)).clamp(0.0, 1.0);
                let scale = if lab.x > 0.0 { l / lab.x } else { 0.0 };
                Vec3::new(l, lab.y * scale, lab.z * scale)
            }
        }
    }
}

impl Palette {
    /// The scene lightness whose [`Palette::target`] has lightness `l`.
    fn untarget_lightness(self, l: f32, stretch: (f32, f32)) -> f32 {
        match self {
            Palette::Xterm256 => l,
            Palette::Ansi16 => stretch.0 + l * (stretch.1 - stretch.0),
        }
    }
}

/// The scene lightness (OKLab L) stretched to 0 and to 1 in 16 colours (see [`Palette::target`]).
const STRETCH_16: (f32, f32) = (0.25, 0.65);
/// [`STRETCH_16`] for grey walls (issue #39): their greys are the light grey and white only (the dark
/// grey is the floor's, black for what is near black), so their lightness is stretched further down:
/// white up close, light grey further off.
const STRETCH_16_GREY_WALL: (f32, f32) = (0.1, 0.55);

/// One palette entry as the ramps see it.
#[derive(Clone, Copy, Debug)]
struct RampEntry {
    index: u8,
    lab: Vec3,
    chroma: f32,
    /// Hue angle (radians).
    hue: f32,
}

/// A palette's entries in order of lightness (then index), built on first use.
fn ramp_entries(palette: Palette) -> &'static [RampEntry] {
    static SORTED: [OnceLock<Vec<RampEntry>>; 2] = [OnceLock::new(), OnceLock::new()];
    SORTED[palette as usize].get_or_init(|| {
        let oklab_of = &entries().oklab;
        let mut sorted: Vec<RampEntry> = palette
            .indices()
            .map(|index| {
                let lab = oklab_of[usize::from(index)];
                RampEntry { index, lab, chroma: lab.y.hypot(lab.z), hue: lab.z.atan2(lab.y) }
            })
            .collect();
        sorted.sort_by(|a, b| a.lab.x.total_cmp(&b.lab.x).then(a.index.cmp(&b.index)));
        sorted
    })
}

/// Chromaticities are looked up on a grid of `r / (r + g + b)` and `g / (r + g + b)` (linear) in steps
/// of `1 / CHROMA_STEPS`; a surface lit by white light and fogged toward black keeps its chromaticity
/// at every distance and angle, so it keeps its ramp.
pub(crate) const CHROMA_STEPS: usize = 96;
const SLOTS: usize = (CHROMA_STEPS + 1) * (CHROMA_STEPS + 1);
/// A ramp is chosen at this many lightness levels from black to the brightest colour of its
/// chromaticity.
const LEVELS: usize = 64;
/// Below this intensity (`r + g + b`, linear) a colour is black.
const BLACK: f32 = 1e-6;

/// A light ramp: the palette entries a surface of one chromaticity shows as its light changes, from
/// dark to light. Entries are in order of lightness and each holds one run of intensities, so a wall
/// darkens along its own ramp in clean bands instead of jumping between unrelated entries; each is
/// chosen for its hue as well as its lightness.
///
/// Built by dynamic programming over 64 lightness levels of the chromaticity: of the sequences
/// of entries non-decreasing in lightness, made of greys and of entries within the palette's
/// [`hue_span`](Palette::hue_span) of the chromaticity's hue, greys only below the coloured ones, the
/// one with the least total cost (lightness, hue and chroma weighed as a viewer weighs them, a grey
/// for a coloured sample dearest) plus the cost of its steps (a change of chroma between coloured
/// entries).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LightRamp {
    /// `starts[k]`: the intensity (`r + g + b`, linear) from which `entries[k + 1]` is shown.
    starts: Vec<f32>,
    entries: Vec<u8>,
    /// `centres[k]`: the intensity at which the chromaticity has the lightness of `entries[k]` (as the
    /// palette aims at it, [`Palette::target`]): where a mix of it with a neighbour is all of it.
    centres: Vec<f32>,
    /// `close[k]`: whether `entries[k]` and `entries[k + 1]` are close enough to mix
    /// ([`LightRamp::entry_dithered`]).
    close: Vec<bool>,
    /// `first[q]`: how many of `starts` lie in buckets below `q` ([`LightRamp::bucket`]): the entry
    /// at an intensity in bucket `q` is `entries[first[q]]` unless a start in that bucket lies below
    /// it. A table read and a comparison a sample, where a search over `starts` was several.
    first: [u8; BUCKETS],
    /// Buckets per unit of intensity: [`BUCKETS`] over the chromaticity's intensities.
    per_bucket: f32,
}

/// How many buckets [`LightRamp::index`] divides a ramp's intensities into: many times its entries
/// (at most a few tens), so that a bucket seldom holds a start (the starts crowd toward black, where a bucket may
/// hold several; each is one comparison more).
const BUCKETS: usize = 256;

/// What a chromaticity is in the scene, for the 16 colours' ramps (issue #39: a black ceiling, far grey
/// walls merging into the grey floor): the floor and the ceiling each have a chromaticity of their own
/// ([`FLOOR_SRGB`], [`CEILING_SRGB`]); anything else is a wall (or a figure, the exit's glow).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Surface {
    /// The floor: [`FLOOR_16`] alone, near and far (as the ceiling: where 16 colours leave out a
    /// far cell line that truecolor shows, the floor's own light below [`NEAR_BLACK`] was a black
    /// sliver under a corridor's end wall).
    Floor,
    /// The ceiling: [`CEILING_16`] alone, near and far (issue #39: its far band, fogged below
    /// [`NEAR_BLACK`] where 16 colours leave out the cell lines that crowd toward the horizon, was a
    /// black strip above a corridor's end wall).
    Ceiling,
    /// A wall: never the floor's or the ceiling's entry, black only where it is near black.
    Wall,
}

/// The floor's entry in 16 colours: the dark grey (xterm's 127).
pub(crate) const FLOOR_16: u8 = 8;
/// The ceiling's entry in 16 colours: the dark blue, a night sky over the grey floor, never black (the
/// other greys are the floor's or lighter than any ceiling; black is for what is black).
pub(crate) const CEILING_16: u8 = 4;
/// The light grey and the white of the 16 colours: no coloured wall's ramp holds them (its greys are
/// its dark end, and these are lighter than its hue's entries), so they are grey walls', door jambs'
/// (`shade::jamb_grey`: light ticks at an opening, issue #39) and the floor's and ceiling's lines'.
#[cfg(test)]
pub(crate) const LIGHT_GREYS_16: [u8; 2] = [7, 15];
/// In 16 colours, a sample of the scene darker than this (OKLab L) may be black; a lighter one never is.
pub const NEAR_BLACK: f32 = 0.2;
/// The exit's glow on a wall in 16 colours (the dark green, xterm's 2): see [`glow_16`].
pub(crate) const GLOW_16: u8 = 2;

/// Whether a chromaticity `direction` (OKLab, any scale) is the exit's green: coloured and within 25°
/// of the beacon's hue (generated walls are never green: only the exit's light, the beacon and a
/// course file's green wall are). In 16 colours the dark green ([`GLOW_16`]) is for these alone: a
/// dark yellow or cyan wall's ramp may not take it, so no unlit generated wall shows the glow's look.
fn exit_green(direction: Vec3) -> bool {
    let glow = oklab(crate::sprite::EXIT_GLOW);
    let (chroma, hue) = (direction.y.hypot(direction.z), direction.z.atan2(direction.y));
    direction.x > 0.0
        && chroma > GREY_ENTRY * direction.x
        && hue_difference(hue, glow.z.atan2(glow.y)) <= 25f32.to_radians()
}

/// Whether a wall of chromaticity `direction` shows the exit's glow in 16 colours (issue #39): the
/// glow's very hue (within 8° of the beacon's: the exit's light gives every surface it lights that
/// hue, and a course file's sage or teal walls, further off or paler, keep their own ramps) and a
/// chroma share of the glow's (chroma ⁄ lightness 0.085–0.155: the faintest glow has 0.09, the
/// beacon 0.18). Such a wall shows [`GLOW_16`] (black where near black) and nothing else: its ramp
/// would otherwise climb to bright cyan or the bright green, a wall's hue or the beacon's (xterm's 10).
fn glow_16(direction: Vec3) -> bool {
    let glow = oklab(crate::sprite::EXIT_GLOW);
    let (chroma, hue) = (direction.y.hypot(direction.z), direction.z.atan2(direction.y));
    let glow_hue = hue_difference(hue, glow.z.atan2(glow.y)) <= 8f32.to_radians();
    glow_hue && (0.085..0.155).contains(&(chroma / direction.x.max(1e-6)))
}

/// Whether a wall sample of linear colour `linear` shows the exit's glow in 16 colours ([`glow_16`]):
/// there every lit wall is the one dark green, so the edge pass draws its seams and corners apart
/// ([`glow_line_16`]).
#[must_use]
pub(crate) fn glow_lit_16(linear: Vec3) -> bool {
    let chroma = linear.max(Vec3::ZERO);
    chroma.max_element() > 0.0 && glow_16(oklab(chroma))
}

/// A seam or corner on a wall lit by the exit's glow, in 16 colours: the dark cyan (xterm's 6). The
/// glow's ramp there holds only black and the dark green ([`GLOW_16`]), and a seam at 0.7 or an edge
/// at 0.5 of the wall's light stays the dark green, so between two lit walls no seam and no corner
/// showed (issue #39: 1 of 586 seams). Not black (black is for what is near black), not the dark grey
/// (the floor's), not the bright green (the beacon's), not the light grey (a jamb's: an opening).
#[must_use]
pub(crate) fn glow_line_16() -> Vec3 {
    Vec3::new(0.0, 0.3, 0.3)
}

/// The surface whose chromaticity slot is `slot` ([`Surface`]).
fn surface_of(slot: usize) -> Surface {
    static SLOTS: OnceLock<(Option<usize>, Option<usize>)> = OnceLock::new();
    let (floor, ceiling) = *SLOTS.get_or_init(|| {
        let of = |srgb: Vec3| self::slot(srgb.map(srgb_to_linear)).map(|(slot, _)| slot);
        (of(FLOOR_SRGB), of(CEILING_SRGB))
    });
    if Some(slot) == floor {
        Surface::Floor
    } else if Some(slot) == ceiling {
        Surface::Ceiling
    } else {
        Surface::Wall
    }
}

/// `linear` moved off the floor's and the ceiling's chromaticity slots, for a wall (or a mark on one):
/// in 16 colours those slots show only the floor's and the ceiling's entries ([`Surface`]), so a wall
/// of the floor's very tint would show as the floor. A warmer (floor) or cooler (ceiling) tint by 8 %
/// of one channel moves it about two slots on; any other colour comes back as it is.
#[must_use]
pub(crate) fn off_floor_and_ceiling(linear: Vec3) -> Vec3 {
    let mut colour = linear;
    for _ in 0..4 {
        match slot(colour).map(|(slot, _)| surface_of(slot)) {
            Some(Surface::Floor) => colour.x = (colour.x * 1.08).max(colour.x + 1e-4),
            Some(Surface::Ceiling) => colour.z = (colour.z * 1.08).max(colour.z + 1e-4),
            _ => break,
        }
    }
    colour
}

impl LightRamp {
    /// The ramp of the chromaticity `chroma` (linear RGB, any scale) in `palette`, for a wall.
    #[must_use]
    #[cfg(test)]
    pub fn new(chroma: Vec3, palette: Palette) -> LightRamp {
        LightRamp::of_surface(chroma, palette, Surface::Wall)
    }

    /// The ramp of the chromaticity `chroma` (linear RGB, any scale) in `palette` for `surface`: in 16
    /// colours the floor shows [`FLOOR_16`] and the ceiling [`CEILING_16`] (neither ever black), a wall neither,
    /// and nothing is black where the scene is lighter than [`NEAR_BLACK`]; in 256 colours the surface
    /// does not matter.
    #[must_use]
    pub(crate) fn of_surface(chroma: Vec3, palette: Palette, surface: Surface) -> LightRamp {
        let chroma = chroma.max(Vec3::ZERO);
        let sum = chroma.x + chroma.y + chroma.z;
        let chroma = if sum > 0.0 && sum.is_finite() { chroma / sum } else { Vec3::splat(1.0 / 3.0) };
        // Intensity t: the colour is t · chroma; OKLab scales by t^(1/3) (its cube roots of a linear
        // map), so level s = t^(1/3) aims at s · oklab(chroma), up to the brightest t, where a channel
        // reaches 1.
        let direction = oklab(chroma);
        let s_max = (1.0 / chroma.max_element()).cbrt();
        // Greys, and the entries of the chromaticity's own hue: a ramp never passes through another.
        let hue = direction.z.atan2(direction.y);
        let coloured = direction.y.hypot(direction.z) * s_max >= COLOURED;
        let sixteen = palette == Palette::Ansi16;
        let grey_wall = surface == Surface::Wall && !coloured;
        let stretch = if grey_wall { STRETCH_16_GREY_WALL } else { STRETCH_16 };
        let glow = sixteen && surface == Surface::Wall && glow_16(direction);
        let candidates: Vec<RampEntry> = ramp_entries(palette)
            .iter()
            .filter(|e| match (sixteen, surface) {
                (true, Surface::Floor) => e.index == FLOOR_16,
                (true, Surface::Ceiling) => e.index == CEILING_16,
                (true, Surface::Wall) if glow => e.index == 0 || e.index == GLOW_16,
                (true, Surface::Wall) if e.index == GLOW_16 && !exit_green(direction) => false,
                (true, Surface::Wall) if e.index == FLOOR_16 || e.index == CEILING_16 => false,
                _ => e.chroma < GREY_ENTRY || (coloured && hue_difference(e.hue, hue) <= palette.hue_span()),
            })
            .copied()
            .collect();
        let n = candidates.len();
        // best[j]: the least cost of levels 0..=level ending on candidate j; from[level][j]: the
        // candidate of the level before on that path. A step from candidate i to a lighter j: from a
        // grey, free; from a coloured entry to a grey, never (a ramp's greys are its dark end: once
        // coloured it stays so, and a wall is never a grey blob amid its colour); between two
        // coloured entries, [`Weights::step`] times their chroma difference squared (a wall's bands
        // keep its saturation instead of passing through a vivid entry between two pale ones).
        // (the exit's green, muted at every lightness: greys a little further up, [`Weights::muted_glow`])
        let relative = direction.y.hypot(direction.z) / direction.x.max(1e-6);
        let weights = match palette.weights() {
            w if exit_green(direction) && relative <= w.muted_glow.0 => {
                Weights { muted: w.muted_glow.1, ..w }
            }
            w => w,
        };
        let grey: Vec<bool> = candidates.iter().map(|e| e.chroma < GREY_ENTRY).collect();
        let coloured: Vec<usize> = (0..n).filter(|&i| !grey[i]).collect();
        // The cost of a step from each coloured candidate to each lighter coloured one, the same for
        // every level: `steps[k]`, k = the coloured j's row start + the coloured i's place.
        let mut row_start = vec![0usize; n];
        let mut steps = Vec::with_capacity(coloured.len() * coloured.len().saturating_sub(1) / 2);
        for (place, &j) in coloured.iter().enumerate() {
            row_start[j] = steps.len();
            steps.extend(
                coloured[..place]
                    .iter()
                    .map(|&i| weights.step * (candidates[i].chroma - candidates[j].chroma).powi(2)),
            );
        }
        let places: Vec<usize> = (0..n).map(|j| coloured.partition_point(|&i| i < j)).collect();
        let mut best = vec![0.0f32; n];
        let mut next = vec![0.0f32; n];
        let mut best_coloured = vec![0.0f32; coloured.len()];
        let mut from = vec![0u8; LEVELS * n];
        for level in 0..LEVELS {
            let s = s_max * (level as f32 + 0.5) / LEVELS as f32;
            let target = palette.target(direction * s, stretch);
            let (target_chroma, target_hue) = (target.y.hypot(target.z), target.z.atan2(target.y));
            for (b, &i) in best_coloured.iter_mut().zip(&coloured) {
                *b = best[i];
            }
            // The best path so far ending on a grey no lighter than j: a step from it costs nothing.
            let mut from_grey = (f32::INFINITY, 0usize);
            for j in 0..n {
                let (mut before, mut at) = (if level == 0 { 0.0 } else { best[j] }, j);
                if level > 0 {
                    if from_grey.0 < before {
                        (before, at) = from_grey;
                    }
                    if !grey[j] {
                        // (the coloured candidates below j, each its step to j)
                        let place = places[j];
                        let steps = &steps[row_start[j]..][..place];
                        if let Some((cost, k)) = least_step(before, &best_coloured[..place], steps) {
                            (before, at) = (cost, coloured[k]);
                        }
                    }
                    if grey[j] && best[j] < from_grey.0 {
                        from_grey = (best[j], j);
                    }
                }
                from[level * n + j] = at as u8;
                // (16 colours: black only where the scene is near black, over the whole level: a
                // level spans lightness up to its top, and one whose centre is below NEAR_BLACK but
                // its top above it drew samples of L 0.2 black, issue #39)
                let top = direction.x * s_max * (level + 1) as f32 / LEVELS as f32;
                let unblack = sixteen && candidates[j].index == 0 && top >= NEAR_BLACK;
                let cost = if unblack {
                    1e6
                } else {
                    cost(target, target_chroma, target_hue, &candidates[j], &weights)
                };
                next[j] = before + cost;
            }
            std::mem::swap(&mut best, &mut next);
        }
        let mut at = (0..n).min_by(|&a, &b| best[a].total_cmp(&best[b])).unwrap_or(0);
        let mut path = vec![0usize; LEVELS];
        for level in (0..LEVELS).rev() {
            path[level] = at;
            at = usize::from(from[level * n + at]);
        }
        let (mut starts, mut entries) = (Vec::new(), vec![candidates[path[0]].index]);
        for level in 1..LEVELS {
            if path[level] != path[level - 1] {
                let s = s_max * level as f32 / LEVELS as f32;
                starts.push(s * s * s);
                entries.push(candidates[path[level]].index);
            }
        }
        let oklab_of = &self::entries().oklab;
        let centres = entries
            .iter()
            .map(|&e| {
                let l = palette.untarget_lightness(oklab_of[usize::from(e)].x, stretch);
                let s = if direction.x > 0.0 { (l / direction.x).min(s_max) } else { 0.0 };
                s * s * s
            })
            .collect();
        let close = entries
            .windows(2)
            .map(|pair| oklab_of[usize::from(pair[0])].distance(oklab_of[usize::from(pair[1])]) <= MIX_STEP)
            .collect();
        // Buckets over 0..=the brightest intensity (any positive scale would be exact; this one
        // spreads the starts).
        let top = s_max * s_max * s_max;
        let per_bucket = if top > 0.0 && top.is_finite() { BUCKETS as f32 / top } else { 0.0 };
        let mut ramp = LightRamp { starts, entries, centres, close, first: [0; BUCKETS], per_bucket };
        let below = |q: usize| ramp.starts.iter().filter(|&&start| ramp.bucket(start) < q).count();
        let first = std::array::from_fn(|q| u8::try_from(below(q)).expect("at most LEVELS starts"));
        ramp.first = first;
        ramp
    }

    /// The bucket of intensity `t` in [`LightRamp::first`]: non-decreasing in `t` (a product by a
    /// positive constant, truncated, clamped), so a start in a lower bucket than `t`'s lies below `t`,
    /// and one in a higher bucket above it.
    #[inline]
    fn bucket(&self, t: f32) -> usize {
        ((t * self.per_bucket) as usize).min(BUCKETS - 1)
    }

    /// How many of the ramp's starts lie at or below intensity `t` (`starts.partition_point(|&s| t >=
    /// s)`, NaN: 0): those of the buckets below `t`'s, by the table, then those of its own bucket.
    #[inline]
    fn index(&self, t: f32) -> usize {
        let mut k = usize::from(self.first[self.bucket(t)]);
        while k < self.starts.len() && t >= self.starts[k] {
            k += 1;
        }
        k
    }

    /// The ramp's entries, darkest first.
    #[must_use]
    #[cfg(test)]
    pub fn entries(&self) -> &[u8] {
        &self.entries
    }

    /// The entry shown at intensity `t` (`r + g + b`, linear).
    #[must_use]
    #[inline]
    pub fn entry(&self, t: f32) -> u8 {
        self.entries[self.index(t)]
    }

    /// The entry shown at intensity `t` on a sample whose ordered-dither threshold is `threshold`
    /// ([`threshold`], in (0, 1)): between the centres of two neighbouring entries that are
    /// [close](MIX_STEP), a mix of the two in proportion to where `t` lies between them (the
    /// lighter on the samples whose threshold is below its share); elsewhere [`LightRamp::entry`].
    #[must_use]
    #[inline]
    pub(crate) fn entry_dithered(&self, t: f32, threshold: f32) -> u8 {
        let k = self.index(t);
        let pair = if t < self.centres[k] && k > 0 && self.close[k - 1] {
            k - 1
        } else if t > self.centres[k] && k + 1 < self.entries.len() && self.close[k] {
            k
        } else {
            return self.entries[k];
        };
        let (low, high) = (self.centres[pair], self.centres[pair + 1]);
        let share = if high > low { (t - low) / (high - low) } else { 0.0 };
        self.entries[if share > threshold { pair + 1 } else { pair }]
    }
}

/// A scan of `k` in order for `best[k] + steps[k]` less than `before`, each found the new `before`:
/// the last found and its `k` (`None` if none is). Eight sums at a time: eight none of which is less
/// than `before` change nothing and are passed with one test; eight with one that is, in order.
fn least_step(mut before: f32, best: &[f32], steps: &[f32]) -> Option<(f32, usize)> {
    let n = best.len().min(steps.len());
    let mut found = None;
    let mut scan = |range: std::ops::Range<usize>, before: &mut f32| {
        for k in range {
            let sum = best[k] + steps[k];
            if sum < *before {
                (*before, found) = (sum, Some(k));
            }
        }
    };
    let whole = n - n % 8;
    for start in (0..whole).step_by(8) {
        let b = f32x8::from(<[f32; 8]>::try_from(&best[start..start + 8]).expect("eight"));
        let s = f32x8::from(<[f32; 8]>::try_from(&steps[start..start + 8]).expect("eight"));
        // (the same sums, lane by lane; NaN is never less)
        if (b + s).simd_lt(f32x8::splat(before)).any() {
            scan(start..start + 8, &mut before);
        }
    }
    scan(whole..n, &mut before);
    found.map(|k| (before, k))
}

/// [`least_step`] as the plain scan in order it stands for: the oracle.
#[cfg(test)]
fn least_step_in_order(mut before: f32, best: &[f32], steps: &[f32]) -> Option<(f32, usize)> {
    let mut found = None;
    for (k, (b, s)) in best.iter().zip(steps).enumerate() {
        if b + s < before {
            before = b + s;
            found = Some((before, k));
        }
    }
    found
}

/// Two palette entries this close (OKLab) or closer are mixed by [`LightRamp::entry_dithered`]: a
/// pattern of them is seen as their mix, not as grain (issue #33's grain is a pair of neighbours more
/// than this further apart than in truecolor).
pub(crate) const MIX_STEP: f32 = 0.06;

/// The ordered-dither threshold of sample `(x, y)` (sample grid, origin top-left), in (0, 1): the 2×2
/// Bayer matrix tiled over the sample grid, anchored to the screen so a still picture keeps its
/// pattern and the diff encoder sends nothing for it.
#[must_use]
#[inline]
pub fn threshold(x: usize, y: usize) -> f32 {
    const BAYER2: [[u8; 2]; 2] = [[0, 2], [3, 1]];
    (f32::from(BAYER2[y % 2][x % 2]) + 0.5) / 4.0
}

/// The chromaticity slot of a linear colour (clamped to 0..1, NaN as 0) and its intensity `r + g + b`;
/// `None` for black.
#[inline]
fn slot(linear: Vec3) -> Option<(usize, f32)> {
    let c = linear.max(Vec3::ZERO).min(Vec3::ONE);
    let t = c.x + c.y + c.z;
    if t < BLACK {
        return None;
    }
    let scale = CHROMA_STEPS as f32 / t;
    let (r, g) = (round_non_negative(c.x * scale), round_non_negative(c.y * scale));
    Some((r.min(CHROMA_STEPS) * (CHROMA_STEPS + 1) + g.min(CHROMA_STEPS), t))
}

/// `x.round() as usize` (halves away from zero; NaN and negatives 0) for `x` below 2^32, without
/// `f32::round`, a library call on baseline x86-64 (no SSE4.1): truncate, then one more where the
/// fraction left is a half or more (`x` less its whole part is exact: the part is 0, or at least half
/// of `x`). Not `(x + 0.5) as usize`, which rounds 0.49999997 up.
#[inline]
fn round_non_negative(x: f32) -> usize {
    let whole = x as u32; // saturating: NaN and negatives give 0, whose fraction is below a half
    whole as usize + usize::from(x - whole as f32 >= 0.5)
}

/// The ramp of a chromaticity slot, built on first use: a frame pays only for the chromaticities it
/// shows (a few tens: each wall colour, floor, ceiling, the exit's glow), each about 20 µs, and they
/// stay for the process's later frames.
fn slot_ramp(slot: usize, palette: Palette) -> &'static LightRamp {
    static RAMPS: [[OnceLock<Box<LightRamp>>; SLOTS]; 2] =
        [const { [const { OnceLock::new() }; SLOTS] }, const { [const { OnceLock::new() }; SLOTS] }];
    RAMPS[palette as usize][slot].get_or_init(|| {
        let (r, g) = (slot / (CHROMA_STEPS + 1), slot % (CHROMA_STEPS + 1));
        let step = 1.0 / CHROMA_STEPS as f32;
        let chroma = Vec3::new(r as f32 * step, g as f32 * step, (1.0 - (r + g) as f32 * step).max(0.0));
        Box::new(LightRamp::of_surface(chroma, palette, surface_of(slot)))
    })
}

/// The light ramp of `linear`'s chromaticity in `palette` (of grey for black).
#[must_use]
#[cfg(test)]
pub(crate) fn light_ramp(linear: Vec3, palette: Palette) -> &'static LightRamp {
    let grey = (CHROMA_STEPS / 3) * (CHROMA_STEPS + 1) + CHROMA_STEPS / 3;
    slot_ramp(slot(linear).map_or(grey, |(slot, _)| slot), palette)
}

/// The entry of `palette` showing a linear colour: the entry of its chromaticity's [`LightRamp`] at
/// its intensity (black: the palette's darkest).
#[must_use]
#[inline]
pub fn ramp_entry(linear: Vec3, palette: Palette) -> u8 {
    match slot(linear) {
        Some((slot, t)) => slot_ramp(slot, palette).entry(t),
        None => ramp_entries(palette)[0].index,
    }
}

/// [`ramp_entry`] on a sample whose ordered-dither threshold is `threshold`
/// ([`LightRamp::entry_dithered`]).
#[must_use]
#[inline]
pub(crate) fn ramp_entry_dithered(linear: Vec3, palette: Palette, threshold: f32) -> u8 {
    match slot(linear) {
        Some((slot, t)) => slot_ramp(slot, palette).entry_dithered(t, threshold),
        None => ramp_entries(palette)[0].index,
    }
}

/// A linear colour as the picture shows it at `depth`: exact in truecolor, its [`ramp_entry`] in 256
/// and 16 colours, the default colour without colour.
#[must_use]
pub(crate) fn picture_color(linear: Vec3, depth: ColorDepth) -> Color {
    match Palette::of(depth) {
        Some(palette) => Color::Indexed(ramp_entry(linear, palette)),
        None => quantize(linear, depth),
    }
}

/// The lookup as it was before the bucket tables (issue #42), kept as the oracle: the slot by
/// `f32::round`, the entry by a binary search of the ramp's starts.
#[cfg(test)]
pub(crate) mod search {
    use super::*;

    fn slot(linear: Vec3) -> Option<(usize, f32)> {
        let c = linear.max(Vec3::ZERO).min(Vec3::ONE);
        let t = c.x + c.y + c.z;
        if t < BLACK {
            return None;
        }
        let scale = CHROMA_STEPS as f32 / t;
        let (r, g) = ((c.x * scale).round() as usize, (c.y * scale).round() as usize);
        Some((r.min(CHROMA_STEPS) * (CHROMA_STEPS + 1) + g.min(CHROMA_STEPS), t))
    }

    pub fn entry(ramp: &LightRamp, t: f32) -> u8 {
        ramp.entries[ramp.starts.partition_point(|&start| t >= start)]
    }

    pub fn entry_dithered(ramp: &LightRamp, t: f32, threshold: f32) -> u8 {
        let k = ramp.starts.partition_point(|&start| t >= start);
        let pair = if t < ramp.centres[k] && k > 0 && ramp.close[k - 1] {
            k - 1
        } else if t > ramp.centres[k] && k + 1 < ramp.entries.len() && ramp.close[k] {
            k
        } else {
            return ramp.entries[k];
        };
        let (low, high) = (ramp.centres[pair], ramp.centres[pair + 1]);
        let share = if high > low { (t - low) / (high - low) } else { 0.0 };
        ramp.entries[if share > threshold { pair + 1 } else { pair }]
    }

    /// [`ramp_entry`](super::ramp_entry), and [`ramp_entry_dithered`] with a threshold, by the oracle.
    pub fn ramp_entry(linear: Vec3, palette: Palette, threshold: Option<f32>) -> u8 {
        match slot(linear) {
            Some((slot, t)) => {
                let ramp = slot_ramp(slot, palette);
                threshold.map_or_else(|| entry(ramp, t), |threshold| entry_dithered(ramp, t, threshold))
            }
            None => ramp_entries(palette)[0].index,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ramps' step search eight sums at a time finds what the scan in order finds, sum bits and
    /// place: rows of 0–40 sums drawn from a few values (ties, both zeros, infinities, NaN) against
    /// several starting costs, and rows where the least sum comes late, early or twice.
    #[test]
    fn least_step_is_the_scan_in_order() {
        let values = [0.0, -0.0, 0.25, 0.5, 0.5, 1.0, 2.0, 3.0, f32::INFINITY, f32::NAN, 1e-7];
        let mut state = 7u64;
        let mut pick = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            values[(state >> 33) as usize % values.len()]
        };
        let bits = |r: Option<(f32, usize)>| r.map(|(v, k)| (v.to_bits(), k));
        let (mut rows, mut found) = (0, 0);
        for n in 0..=40 {
            for _ in 0..60 {
                let best: Vec<f32> = (0..n).map(|_| pick()).collect();
                let steps: Vec<f32> = (0..n).map(|_| pick()).collect();
                for before in [f32::INFINITY, 4.0, 1.0, 0.5, 0.0, f32::NAN] {
                    let fast = least_step(before, &best, &steps);
                    assert_eq!(
                        bits(fast),
                        bits(least_step_in_order(before, &best, &steps)),
                        "{best:?} {steps:?}"
                    );
                    rows += 1;
                    found += usize::from(fast.is_some());
                }
            }
        }
        // the least late in a long row, twice, and a row of equal sums
        let mut best = vec![5.0; 37];
        best[30] = 1.0;
        best[35] = 1.0;
        let steps = vec![0.5; 37];
        assert_eq!(least_step(10.0, &best, &steps), Some((1.5, 30)));
        assert_eq!(least_step(10.0, &[1.0; 19], &[1.0; 19]), Some((2.0, 0)));
        assert_eq!(least_step(2.0, &[1.0; 19], &[1.0; 19]), None);
        assert!(rows > 10_000 && found > rows / 4, "{found} of {rows}");
    }

    #[test]
    fn pure_colours_map_to_their_obvious_indices() {
        assert_eq!(xterm256([255, 0, 0]), 196);
        assert_eq!(xterm256([0, 255, 0]), 46);
        assert_eq!(xterm256([0, 0, 255]), 21);
        assert_eq!(xterm256([0, 0, 0]), 16);
        assert_eq!(xterm256([255, 255, 255]), 231);
        assert_eq!(ansi16([255, 0, 0]), 9);
        assert_eq!(ansi16([0, 0, 0]), 0);
        assert_eq!(ansi16([200, 200, 200]), 7);
        assert_eq!(quantize(Vec3::new(1.0, 0.0, 0.0), ColorDepth::TrueColor), Color::Rgb(255, 0, 0));
        assert_eq!(quantize(Vec3::ONE, ColorDepth::None), Color::Default);
    }

    #[test]
    fn xterm256_tables_match_the_direct_search() {
        // The search the tables are built from, written out per colour.
        let reference = |rgb: [u8; 3]| {
            let level = |v: u8| (0..6).min_by_key(|&k| CUBE_LEVELS[k].abs_diff(v)).unwrap_or(0);
            let [r, g, b] = rgb.map(level);
            let cube = (16 + 36 * r + 6 * g + b) as u8;
            let mean = (u32::from(rgb[0]) + u32::from(rgb[1]) + u32::from(rgb[2])) as f32 / 3.0;
            let grey = 232 + ((mean - 8.0) / 10.0).round().clamp(0.0, 23.0) as u8;
            if distance2(xterm_rgb(grey), rgb) < distance2(xterm_rgb(cube), rgb) { grey } else { cube }
        };
        // Every 13th colour (checked exhaustively once; all 2^24 take a while in the test profile).
        for key in (0..1u32 << 24).step_by(13) {
            let rgb = [(key >> 16) as u8, (key >> 8) as u8, key as u8];
            assert_eq!(xterm256(rgb), reference(rgb), "{rgb:?}");
        }
    }

    #[test]
    fn greys_go_to_the_grey_ramp() {
        for (v, index) in [(8, 232), (128, 244), (238, 255), (100, 241)] {
            assert_eq!(xterm256([v, v, v]), index, "grey {v}");
        }
        // Cube greys that are exact stay in the cube.
        assert_eq!(xterm256([95, 95, 95]), 59);
    }

    #[test]
    fn every_palette_entry_round_trips() {
        for index in 16..=255u8 {
            let rgb = xterm_rgb(index);
            assert_eq!(xterm_rgb(xterm256(rgb)), rgb, "index {index}");
        }
        for (index, &rgb) in ANSI16.iter().enumerate() {
            assert_eq!(usize::from(ansi16(rgb)), index);
        }
    }

    fn linear(rgb: [u8; 3]) -> Vec3 {
        Vec3::from_array(rgb.map(|v| srgb_to_linear(f32::from(v) / 255.0)))
    }

    fn lab_of(index: u8) -> Vec3 {
        entries().oklab[usize::from(index)]
    }

    fn is_grey(index: u8) -> bool {
        let lab = lab_of(index);
        lab.y.hypot(lab.z) < GREY_ENTRY
    }

    /// A chromaticity: linear RGB with at least one channel above zero.
    fn arb_chroma() -> impl proptest::strategy::Strategy<Value = Vec3> {
        use proptest::prelude::*;
        (0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0)
            .prop_filter("not black", |(r, g, b)| r + g + b > 1e-3)
            .prop_map(|(r, g, b)| Vec3::new(r, g, b))
    }

    /// The properties of every light ramp (issue #33): its entries in order of lightness, each one run
    /// of intensities; greys only at its dark end, every other entry within the palette's hue span of
    /// the chromaticity's hue; the entry shown never darker for a brighter colour of the chromaticity.
    #[test]
    fn a_light_ramp_is_monotone_in_lightness_and_stays_within_its_hue() {
        use proptest::prelude::*;
        // 256 cases: each builds two ramps by dynamic programming (a few ms each in the test profile).
        proptest!(mazewalk_testkit::config_cases(256), |(chroma in arb_chroma())| {
            let hue = {
                let lab = oklab(chroma / (chroma.x + chroma.y + chroma.z));
                lab.z.atan2(lab.y)
            };
            for palette in [Palette::Xterm256, Palette::Ansi16] {
                let ramp = LightRamp::new(chroma, palette);
                let entries = ramp.entries();
                prop_assert_eq!(entries.len(), ramp.starts.len() + 1);
                prop_assert!(ramp.starts.windows(2).all(|w| w[0] < w[1]), "{:?}", ramp.starts);
                for pair in entries.windows(2) {
                    prop_assert!(pair[0] != pair[1], "{:?}: one run each", entries);
                    prop_assert!(lab_of(pair[0]).x <= lab_of(pair[1]).x, "{:?}: darkest first", entries);
                    prop_assert!(is_grey(pair[0]) || !is_grey(pair[1]), "{:?}: greys at the dark end", entries);
                }
                for &e in entries.iter().filter(|&&e| !is_grey(e)) {
                    let lab = lab_of(e);
                    let off = hue_difference(lab.z.atan2(lab.y), hue);
                    prop_assert!(off <= palette.hue_span() + 1e-4, "{}: {}° off", e, off.to_degrees());
                }
                prop_assert!(entries.iter().all(|&e| palette.indices().contains(&e)));
                // Brighter and brighter colours of the chromaticity: never a darker entry, from the
                // ramp itself and through the lookup. The lookup's slot is the chromaticity rounded
                // to a grid; where it lies within float noise of a half step, scaling the colour can
                // land it in the neighbouring slot (another ramp), so the lookup is held to it within
                // one slot only, and a slot may change only there.
                let scale = chroma / chroma.max_element();
                let (mut last, mut last_lookup, mut last_slot) = (0.0f32, 0.0f32, None);
                for k in 0..=200 {
                    let colour = scale * (k as f32 / 200.0);
                    let shown = lab_of(ramp.entry(colour.element_sum())).x;
                    prop_assert!(shown >= last - 1e-6, "{:?} at {}: {} after {}", chroma, k, shown, last);
                    last = shown;
                    let Some((slot, _)) = slot(colour) else { continue };
                    let looked_up = lab_of(ramp_entry(colour, palette)).x;
                    if last_slot.is_some_and(|s| s != slot) {
                        let grid = colour * (CHROMA_STEPS as f32 / colour.element_sum());
                        let near_half = |x: f32| (x.fract() - 0.5).abs() < 1e-4;
                        prop_assert!(near_half(grid.x) || near_half(grid.y), "{:?}: slot moved at {}", chroma, k);
                    } else {
                        prop_assert!(
                            looked_up >= last_lookup - 1e-6,
                            "{:?} at {}: {} after {}", chroma, k, looked_up, last_lookup
                        );
                    }
                    (last_lookup, last_slot) = (looked_up, Some(slot));
                }
            }
        });
    }

    /// Greys stay grey, in both palettes, and a palette's own colours are shown as themselves or as
    /// an entry within a small step of them.
    #[test]
    fn greys_take_greys_and_palette_colours_come_out_near_themselves() {
        for v in (0..=255u8).step_by(5) {
            let grey = linear([v; 3]);
            for palette in [Palette::Xterm256, Palette::Ansi16] {
                let e = ramp_entry(grey, palette);
                assert!(is_grey(e), "grey {v} in {palette:?}: entry {e}");
            }
        }
        let mut exact = 0;
        for index in 16..=255u8 {
            let shown = ramp_entry(linear(xterm_rgb(index)), Palette::Xterm256);
            let off = lab_of(shown).distance(lab_of(index));
            assert!(off < 0.07, "entry {index} shown as {shown}, {off:.3} off");
            exact += usize::from(shown == index);
        }
        assert!(exact >= 230, "{exact} of 240 entries shown as themselves");
    }

    /// Issue #39: in 16 colours a coloured wall never shows the light grey or the white at any light,
    /// from the fog's dark to full, so a door jamb's grey tick (`shade::jamb_grey`) stands apart from
    /// every wall: over the sRGB cube in steps of 17 (the colours whose ramps are coloured: chroma of
    /// at least `COLOURED` at their brightest) and the generator's table. It held before the jambs
    /// were grey (the light-grey far walls a trial reported were the crowded floor and ceiling lines
    /// and the jambs); the grey jambs rely on it.
    #[test]
    fn in_16_colours_a_coloured_wall_never_takes_the_light_grey_or_white() {
        let mut cube = Vec::new();
        for r in (0..=255u8).step_by(17) {
            for g in (0..=255u8).step_by(17) {
                for b in (0..=255u8).step_by(17) {
                    cube.push([r, g, b]);
                }
            }
        }
        let mut coloured = 0;
        for rgb in cube.into_iter().chain(mazewalk_maze::generate::WALL_COLOURS) {
            let chroma = linear(rgb);
            let sum = chroma.x + chroma.y + chroma.z;
            if sum <= 0.0 {
                continue;
            }
            let brightest = oklab(chroma / sum * (1.0 / (chroma / sum).max_element()));
            if brightest.y.hypot(brightest.z) < COLOURED {
                continue;
            }
            coloured += 1;
            let ramp = LightRamp::new(chroma, Palette::Ansi16);
            assert!(
                !ramp.entries().iter().any(|e| LIGHT_GREYS_16.contains(e)),
                "wall {rgb:?}: entries {:?}",
                ramp.entries()
            );
        }
        assert!(coloured > 3000, "{coloured} coloured walls");
    }

    /// 256 colours keep a wall's hue (issue #33: blue turned violet) without painting it more vivid
    /// than it is (issue #39: a tan wall shown orange): the built-in maze's walls and a generated
    /// maze's pastels, lit and fogged from dim to full, never grey where they have chroma to show,
    /// within 35° of their hue (the cube has few pale entries: a dim pastel's nearest of its own hue
    /// is often twice as saturated), and at most 1.7× their chroma.
    #[test]
    fn in_256_colours_wall_colours_keep_their_hue() {
        for rgb in
            [[0x44, 0x77, 0xaa], [0xcc, 0x88, 0x44], [0x66, 0xaa, 0x55], [150, 120, 180], [190, 140, 110]]
        {
            let wall = linear(rgb);
            for k in 5..=20 {
                let colour = wall * (k as f32 / 20.0);
                let target = oklab(colour);
                if target.y.hypot(target.z) < 0.05 {
                    continue; // as good as grey: the hue error of issue #33 leaves it out
                }
                let shown = lab_of(ramp_entry(colour, Palette::Xterm256));
                let off = hue_difference(shown.z.atan2(shown.y), target.z.atan2(target.y)).to_degrees();
                assert!(!is_grey(ramp_entry(colour, Palette::Xterm256)), "{rgb:?} × {k}/20 shown grey");
                assert!(off <= 35.0, "{rgb:?} × {k}/20: {off:.0}° off");
                let vivid = shown.y.hypot(shown.z) / target.y.hypot(target.z);
                assert!(vivid <= 1.7, "{rgb:?} × {k}/20: {vivid:.2}× the chroma");
            }
        }
    }

    /// Issue #39: in 16 colours only the glow's own hue takes the glow's look: a course file's sage
    /// and teal walls (the CS559 10×10 maze's: 14°–16° off the beacon's hue, or on it but paler) keep
    /// their ramps, and
    /// the surfaces the exit's light tints (every level, walls) take it.
    #[test]
    fn in_16_colours_the_glows_look_is_for_the_glows_hue_alone() {
        let lin = |rgb: [u8; 3]| Vec3::from_array(rgb.map(|v| srgb_to_linear(f32::from(v) / 255.0)));
        for course in [[97, 134, 119], [95, 171, 145], [99, 127, 108]] {
            assert!(!glow_16(oklab(lin(course))), "{course:?}");
        }
        for level in 1..=mazewalk_maze::light::EXIT_LIGHT {
            let lit = crate::shade::exit_tinted(Vec3::splat(0.3), level, 1.0);
            assert!(glow_16(oklab(lit)), "level {level}");
        }
        assert!(!glow_16(oklab(crate::sprite::EXIT_GLOW)), "the beacon keeps its bright green");
    }

    /// Issue #39: the exit's glow on the floor, the floor's colour turned toward the exit's green as
    /// the renderer draws it, at every share of green and every light, steps grey → grey-green →
    /// green in 256 colours: a green (within 15° of the glow's hue) is shown as a grey or as an
    /// entry within 25° of the glow's hue, never olive (110°: on a rim of the glow, 16 % green at
    /// 24 % light, it was; the cube's greens are 142°–164°).
    #[test]
    fn in_256_colours_the_exits_glow_steps_from_grey_to_green_never_through_olive() {
        let floor = FLOOR_SRGB.map(srgb_to_linear);
        let glow = crate::sprite::EXIT_GLOW;
        let green = oklab(glow);
        let green_hue = green.z.atan2(green.y);
        let (mut greys, mut greens) = (0, 0);
        for share in 0..=80 {
            let colour = floor.lerp(glow, share as f32 / 100.0);
            for k in 1..=100 {
                let colour = colour * (k as f32 / 100.0);
                let entry = ramp_entry(colour, Palette::Xterm256);
                let (lab, target) = (lab_of(entry), oklab(colour));
                let hue = lab.z.atan2(lab.y);
                let green = hue_difference(target.z.atan2(target.y), green_hue).to_degrees() <= 15.0;
                let olive = hue_difference(hue, green_hue).to_degrees() > 25.0;
                assert!(
                    is_grey(entry) || !(green && olive),
                    "{share}% green at {k}%: a green shown as entry {entry} {:?}, off the glow's hue",
                    xterm_rgb(entry)
                );
                greys += usize::from(is_grey(entry));
                greens += usize::from(!is_grey(entry) && green);
            }
        }
        assert!(greys > 0 && greens > 0, "{greys} greys, {greens} greens");
    }

    /// Issue #39: a muted warm wall (tan, khaki, beige: OKLab chroma 0.03–0.07, hue 50°–110°) at
    /// every light from a third up, its dark edge lines (half its light) included, is shown as a
    /// grey or as an entry at most 2.4× as saturated as it is: a tan wall's edge was the cube's
    /// orange (135, 95, 0), 2.75× its chroma ((100, 80, 60) at 17/20), where its grey is nearer.
    #[test]
    fn in_256_colours_a_muted_warm_walls_dark_shades_are_never_vivid() {
        let mut walls = 0;
        for r in (100..=250u8).step_by(6) {
            for g in (80..=r).step_by(6) {
                for b in (60..=g).step_by(6) {
                    let wall = linear([r, g, b]);
                    let lab = oklab(wall);
                    let (chroma, hue) = (lab.y.hypot(lab.z), lab.z.atan2(lab.y).to_degrees());
                    if !(0.03..=0.07).contains(&chroma) || !(50.0..=110.0).contains(&hue) {
                        continue;
                    }
                    walls += 1;
                    for k in 7..=20 {
                        let colour = wall * (k as f32 / 20.0);
                        let target = oklab(colour);
                        let entry = ramp_entry(colour, Palette::Xterm256);
                        let shown = lab_of(entry);
                        let vivid = shown.y.hypot(shown.z) / target.y.hypot(target.z);
                        assert!(
                            is_grey(entry) || vivid <= 2.4,
                            "{:?} × {k}/20: entry {entry} {:?}, {vivid:.2}× the chroma",
                            [r, g, b],
                            xterm_rgb(entry)
                        );
                    }
                }
            }
        }
        assert!(walls > 100, "{walls} walls");
    }

    /// Dithering mixes only two neighbouring entries of a ramp that are close, in proportion: the
    /// mean over a 2×2 tile of thresholds moves with the intensity.
    #[test]
    fn dithering_mixes_only_close_neighbours() {
        let mut mixed = 0;
        for rgb in [[128, 128, 128], [0x44, 0x77, 0xaa], [200, 180, 150]] {
            let chroma = linear(rgb);
            for palette in [Palette::Xterm256, Palette::Ansi16] {
                let ramp = light_ramp(chroma, palette);
                let top = 1.0 / (chroma / (chroma.x + chroma.y + chroma.z)).max_element();
                let mut last_mean = 0.0f32;
                for k in 1..=400 {
                    let t = top * k as f32 / 400.0;
                    let plain = ramp.entry(t);
                    let tile: Vec<u8> =
                        (0..4).map(|w| ramp.entry_dithered(t, threshold(w % 2, w / 2))).collect();
                    for &e in &tile {
                        if e != plain {
                            mixed += 1;
                            assert!(
                                lab_of(e).distance(lab_of(plain)) <= MIX_STEP,
                                "{rgb:?}: {e} with {plain}"
                            );
                        }
                    }
                    let mean = tile.iter().map(|&e| lab_of(e).x).sum::<f32>() / 4.0;
                    assert!(mean >= last_mean - 1e-6, "{rgb:?} {palette:?} at {t}: {mean} after {last_mean}");
                    last_mean = mean;
                }
            }
        }
        assert!(mixed > 0, "the greys' close steps are mixed somewhere");
    }

    #[test]
    fn rounding_without_the_library_call_is_f32_round() {
        let mut values =
            vec![0.0, -0.0, f32::NAN, -0.5, -0.49, -3.7, f32::MIN_POSITIVE, 1e-30, 4_294_967_000.0];
        // Every half from 0 to 200 and the floats either side of it (where adding a half and
        // truncating goes wrong: 0.49999997 + 0.5 rounds to 1 in f32).
        for k in 0..=400 {
            let half = k as f32 * 0.5;
            values.extend([half, half.next_down(), half.next_up(), half.next_down().next_down()]);
        }
        // And a spread of magnitudes up to 2^31.
        let mut x = 1e-7f32;
        while x < 2_147_483_648.0 {
            values.extend([x, x * 1.37, x * 2.5, x * 0.7531]);
            x *= 1.9;
        }
        for v in values {
            assert_eq!(round_non_negative(v), v.round() as usize, "{v:e}");
        }
    }

    /// Each ramp's bucket table gives what the search gave, at every start, the floats either side
    /// of it, and intensities spread over the ramp and past its end.
    #[test]
    fn a_ramp_by_buckets_shows_what_the_search_showed() {
        use proptest::prelude::*;
        proptest!(mazewalk_testkit::config_cases(128), |(chroma in arb_chroma())| {
            for palette in [Palette::Xterm256, Palette::Ansi16] {
                let ramp = LightRamp::new(chroma, palette);
                let top = 1.0 / (chroma / (chroma.x + chroma.y + chroma.z)).max_element();
                let mut ts: Vec<f32> = vec![0.0, BLACK, f32::NAN, 3.0, top, top.next_up()];
                for &start in &ramp.starts {
                    ts.extend([start, start.next_down(), start.next_up()]);
                }
                ts.extend((0..=2000).map(|k| top * 1.05 * k as f32 / 2000.0));
                ts.extend((1..=200).map(|k| top * (k as f32 / 200.0).powi(3)));
                for t in ts {
                    prop_assert_eq!(ramp.entry(t), search::entry(&ramp, t), "t = {:e}", t);
                    for q in 0..4 {
                        let threshold = (q as f32 + 0.5) / 4.0;
                        prop_assert_eq!(
                            ramp.entry_dithered(t, threshold),
                            search::entry_dithered(&ramp, t, threshold),
                            "t = {:e}, threshold {}", t, threshold
                        );
                    }
                }
            }
        });
    }

    #[test]
    fn thresholds_cover_every_2x2_window_evenly() {
        for (x0, y0) in [(0, 0), (1, 0), (0, 1), (1, 1), (2, 0), (3, 5), (4, 6)] {
            let mut quarters =
                [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(dx, dy)| (threshold(x0 + dx, y0 + dy) * 4.0) as usize);
            quarters.sort_unstable();
            assert_eq!(quarters, [0, 1, 2, 3], "block at ({x0}, {y0})");
        }
    }

    /// Issue #39: in 16 colours no ramp draws a colour black that is not near black, up to the
    /// lightness where a ramp's level ends (a level's centre below [`NEAR_BLACK`] and its top above
    /// it drew the ceiling at L 0.201 black in ascii); and the ceiling's ramp is its dark blue alone,
    /// near and far (its far band above an end wall was a black strip).
    #[test]
    fn in_16_colours_nothing_lighter_than_near_black_is_black() {
        let step = 1.0 / CHROMA_STEPS as f32;
        let (mut judged, mut ceiling) = (0, 0);
        for r in (0..=CHROMA_STEPS).step_by(3) {
            for g in (0..=CHROMA_STEPS - r).step_by(3) {
                let chroma =
                    Vec3::new(r as f32 * step, g as f32 * step, (1.0 - (r + g) as f32 * step).max(0.0));
                let Some((slot, _)) = slot(chroma) else { continue };
                let surface = surface_of(slot);
                let ramp = LightRamp::of_surface(chroma, Palette::Ansi16, surface);
                let top = 1.0 / chroma.max_element();
                for k in 1..=400 {
                    let t = top * k as f32 / 400.0;
                    let colour = chroma * t;
                    if oklab(colour).x >= NEAR_BLACK {
                        judged += 1;
                        assert_ne!(ramp.entry(t), 0, "{chroma} × {t} ({surface:?}), L {}", oklab(colour).x);
                    }
                }
            }
        }
        let ceiling_chroma = CEILING_SRGB.map(srgb_to_linear);
        for k in 1..=400 {
            let colour = ceiling_chroma * (k as f32 / 400.0);
            assert_eq!(ramp_entry(colour, Palette::Ansi16), CEILING_16, "the ceiling × {k}/400");
            ceiling += 1;
        }
        assert!(judged > 50_000 && ceiling == 400, "{judged} samples judged");
    }
}
