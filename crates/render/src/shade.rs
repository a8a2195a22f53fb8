//! Shading: a headlight along the view axis (Lambert plus ambient), a sun, distance fog, floor and
//! ceiling colours.
//!
//! Small pure functions on linear RGB in 0..1, called per sample by the pipeline's shading closure.
//! Positions and normals are in view space (the eye at the origin); normals come through the normal
//! matrix and need not be unit length.

use glam::{Vec2, Vec3};
use mazewalk_maze::light::EXIT_LIGHT;

/// The power of `|n · axis|` the headlight takes ([`headlight`]): 3, not Lambert's 1, so that a wall
/// turned a little from square on still gets nearly all of it and a wall seen along the view nearly
/// none (at `|n · axis|` 0.4, 0.06 of it against Lambert's 0.4). Issue #39: with generated walls all
/// of one lightness, the headlight is what tells a wall faced square on from a side wall beside it,
/// and at 2–3 cells, where a side wall is a few columns wide and its slant under a row, only that.
pub(crate) const HEADLIGHT_POWER: i32 = 3;

/// The headlight: a lamp the viewer carries, shining along the view axis like a torch's beam (not a
/// bare bulb at the eye): two-sided (walls are seen from both sides), `|n · axis|` to the
/// [`HEADLIGHT_POWER`] for a unit view-space normal, in [0, 1] — `|n.z|³`, the axis being ±z in every
/// convention. Every point of a
/// flat surface gets the same light, so where a palette must step the light, the steps follow the
/// geometry (lines along walls and floor, as depth does), never circles round the centre of the view
/// (issue #39: a light at the eye drew bullseyes on near walls in 256 colours). A wall faced squarely
/// gets all of it, a corridor's side walls none: a wall that blocks the way reads lighter than the
/// walls along it.
#[must_use]
pub fn headlight(unit_normal_view: Vec3) -> f32 {
    if unit_normal_view.is_finite() { unit_normal_view.z.abs().min(1.0).powi(HEADLIGHT_POWER) } else { 1.0 }
}

/// The cosine of the angle between a surface's unit normal and the ray `view` from the eye to the
/// surface point (view space), in [0, 1]: how squarely the ray meets the surface, which sets a
/// sample's footprint on it (a texture's filter). `|n · view| / |view|`; 1.0 where `view` has no
/// usable length (the eye itself).
#[must_use]
pub fn slant_cosine(unit_normal: Vec3, view: Vec3) -> f32 {
    let length = view.length();
    if !(length > 0.0 && length.is_finite()) {
        return 1.0;
    }
    (unit_normal.dot(view).abs() / length).min(1.0)
}

/// Light reaching the eye from a surface: `ambient + (1 - ambient) · diffuse`, so unlit faces keep the
/// `ambient` fraction (0..1) of their colour and faces turned to the headlight get all of it.
#[must_use]
pub fn lit(albedo: Vec3, diffuse: f32, ambient: f32) -> Vec3 {
    albedo * (ambient + (1.0 - ambient) * diffuse.clamp(0.0, 1.0))
}

/// How much more light a wall sends to the eye than the floor at its foot does, at least (the ratio
/// of luminances, both before fog: the fog keeps the same share of both at one distance, so the ratio
/// holds at every distance): [`apart_from_floor`].
pub(crate) const WALL_OVER_FLOOR: f32 = 2.0;

/// The rule that keeps walls apart from floor and ceiling (issue #39, map off: a side wall lit at a
/// grazing angle came out at the floor's lightness and read as open floor): **a wall is lit at least
/// [`WALL_OVER_FLOOR`] times as bright as the floor's lighter square under the same light**,
/// whatever its angle to the eye. It is applied to the wall's colour (`albedo`), before the sun and
/// the headlight: a colour too dark to meet it when the headlight misses the wall (only `ambient`
/// of it left) and the sun is turned away ([`SUN_LOW`]) is raised until it does, its hue kept (scaled;
/// toward white only where scaling would clip a channel). Sun and headlight then multiply it as
/// before, so a corner's two walls and a wall faced squarely still differ as they did. The ceiling is
/// darker than the floor, so a wall is apart from both. Twice the luminance is 1.26× the OKLab
/// lightness: near the eye about 0.12 in L over the floor, still 0.065 where the fog has left the
/// floor at L 0.25, which the 256-colour greys (a step of 0.03–0.04 in L) keep apart. In colour only:
/// without colour the ascii charset tells the floor by its glyphs ([`Renderer`](crate::Renderer)'s `walls_apart`).
#[must_use]
pub(crate) fn apart_from_floor(color: Vec3, floor_luminance: f32, ambient: f32) -> Vec3 {
    let least_light = (ambient * SUN_LOW).max(1e-3);
    let target = (WALL_OVER_FLOOR * floor_luminance / least_light).clamp(0.0, 1.0);
    let y = luminance(color);
    if y >= target || y.is_nan() {
        return color; // bright enough (or NaN: left for the caller's clamps)
    }
    let raised = if y > 1e-6 { (color * (target / y)).min(Vec3::ONE) } else { Vec3::splat(target) };
    let short = luminance(raised);
    if short < target { raised.lerp(Vec3::ONE, (target - short) / (1.0 - short).max(1e-6)) } else { raised }
}

/// The exit's glow's chroma on the floor and the ceiling (walls: [`exit_lit_wall`]) relative to the
/// surface's lightness (OKLab C ⁄ L), times their shares, in the faintest lit
/// cell (level 1, [`EXIT_LIGHT`] − 1 cells of path from the exit) and in the exit's own cell; the
/// levels between step evenly in OKLab chroma, which is close to even in what the eye sees (issue
/// #39: a share of the exit's green mixed in linear RGB, 5 % a level, was lost in 256 colours below
/// about a fifth, and on tan and yellow walls passed through olive). At 0.09 the faintest glow on a
/// generated wall (L 0.75) has chroma 0.068, the cube's pale green (135, 175, 135) (0.072): a palette
/// step off every unlit wall in 256 colours, at every angle and as far as the fog leaves it a green,
/// a side wall the darker (95, 135, 95); from about 0.12 (the last four cells) a wall faced square on
/// shows the cube's greener (95, 175, 135). The top is 0.13 because the cube has so few muted greens:
/// at 0.14 side walls take the faced walls' entry, at 0.16 the floor's cell lines vanish into a green
/// floor, and from 0.18 walls take the vivid (0, 135, 95) and (0, 95, 0), the far beacon's look. Always
/// darker and paler than the beacon's green and white bands at the same distance, which keep a look
/// of their own.
pub(crate) const EXIT_GLOW_CHROMA: (f32, f32) = (0.09, 0.13);

/// The floor's share of the exit's glow ([`EXIT_GLOW_CHROMA`]), against the walls' 1: in 256 colours
/// the only muted green near the floor's lightness is the cube's (95, 135, 95), which a lit side wall
/// shows, so a floor as green as the walls took the side walls' entry and the two merged (the first
/// misreading issue #39 fixed: a side wall read as open floor). At 0.7 the floor keeps its greys
/// there (and its cell lines) and leans green in truecolor.
pub(crate) const FLOOR_EXIT_TINT: f32 = 0.7;

/// The ceiling's share of the exit's glow ([`EXIT_GLOW_CHROMA`]), against the walls' 1: the light is
/// on the ground (the beacon stands on it), the ceiling only catches a fainter glow.
pub(crate) const CEILING_EXIT_TINT: f32 = 0.5;

/// The exit's light at `level` as a colour of luminance 1 (linear): the hue of the beacon's green
/// ([`EXIT_GLOW`](crate::sprite::EXIT_GLOW)), the chroma of [`EXIT_GLOW_CHROMA`] at `level` times
/// `strength` relative to its lightness. (Turned 9° toward the 256-colour cube's greens, 145°, the
/// held-out views' median hue error in 256 colours fell from 8.6° to 5.1°, but every lit wall faced
/// square on took the same pale green there, near the exit and at the edge of the light alike.)
#[must_use]
fn exit_glow_colour(level: u8, strength: f32) -> Vec3 {
    let top = f32::from(EXIT_LIGHT.max(2) - 1);
    let along = f32::from(level.clamp(1, EXIT_LIGHT) - 1) / top;
    glow_colour(strength * (EXIT_GLOW_CHROMA.0 + (EXIT_GLOW_CHROMA.1 - EXIT_GLOW_CHROMA.0) * along))
}

/// The glow's green (the beacon's hue) with chroma `relative` × its lightness (OKLab), as a colour of
/// luminance 1 (linear).
#[must_use]
fn glow_colour(relative: f32) -> Vec3 {
    let direction = glow_direction();
    // (any lightness: OKLab's chroma and lightness scale together as the colour is scaled, so the
    // colour at L 0.75 scaled to luminance 1 keeps C ⁄ L)
    let lightness = 0.75;
    let chroma = lightness * relative;
    let colour =
        linear_from_oklab(Vec3::new(lightness, chroma * direction.x, chroma * direction.y)).max(Vec3::ZERO);
    colour / luminance(colour).max(1e-6)
}

/// The glow's hue (the beacon's) as a unit direction in OKLab's (a, b).
#[must_use]
fn glow_direction() -> Vec2 {
    // Worked out once (three cube roots: the floor's rows ask for every level's colour, a frame in
    // the exit's light over a thousand times).
    static DIRECTION: std::sync::OnceLock<Vec2> = std::sync::OnceLock::new();
    *DIRECTION.get_or_init(|| {
        let hue = crate::palette::oklab(crate::sprite::EXIT_GLOW);
        Vec2::new(hue.y, hue.z).normalize_or_zero()
    })
}

/// A linear sRGB colour from OKLab (Björn Ottosson's inverse of [`oklab`](crate::palette::oklab)).
#[must_use]
fn linear_from_oklab(lab: Vec3) -> Vec3 {
    let l = lab.x + 0.396_337_78 * lab.y + 0.215_803_76 * lab.z;
    let m = lab.x - 0.105_561_346 * lab.y - 0.063_854_17 * lab.z;
    let s = lab.x - 0.089_484_18 * lab.y - 1.291_485_5 * lab.z;
    let (l, m, s) = (l * l * l, m * m * m, s * s * s);
    Vec3::new(
        4.076_741_7 * l - 3.307_711_6 * m + 0.230_969_94 * s,
        -1.268_438 * l + 2.609_757_4 * m - 0.341_319_38 * s,
        -0.004_196_086_3 * l - 0.703_418_6 * m + 1.707_614_7 * s,
    )
}

/// A surface of `color` lit by the exit's light at `level` (0..=`EXIT_LIGHT`, the cell's level:
/// [`mazewalk_maze::light::ExitLight`]): **the exit's green, of the surface's luminance**, its chroma
/// growing from the faintest lit cell to the exit ([`EXIT_GLOW_CHROMA`], times `strength`:
/// [`FLOOR_EXIT_TINT`] for the floor, [`CEILING_EXIT_TINT`] for the ceiling; walls take
/// [`exit_lit_wall`]). The surface's own hue gives way to the glow's, so a lit surface never shows
/// another hue or the olive between a warm colour and green (generated walls are never green, issue
/// #39); its luminance is kept, so the fog and the floor's lines tell the geometry as before. Linear
/// in `color` (the floor's rows tint one colour per level and scale it).
#[must_use]
pub(crate) fn exit_tinted(color: Vec3, level: u8, strength: f32) -> Vec3 {
    if level == 0 {
        return color;
    }
    exit_glow_colour(level, strength) * luminance(color)
}

/// How many steps the exit's light shows on walls in 16 colours over its reach ([`glow_step_16`],
/// [`GLOW_STEPS`]).
pub(crate) const GLOW_STEP_COUNT: usize = 3;

/// The exit's light on a wall in 16 colours ([`exit_lit_wall_16`]) at each of its steps
/// ([`glow_step_16`], from the edge of its reach to the exit; in 256 colours and truecolor walls keep
/// their own hues: [`exit_lit_wall`]): the glow's chroma relative to lightness (OKLab C ⁄ L), the
/// factor on the wall's luminance and the luminance the light adds (linear, before the fog). Every
/// step is the glow's very hue with a chroma share inside `palette::glow_16`'s 0.085–0.155, so 16
/// colours show each as the dark green (xterm's 2; black where near black), the beacon's bright
/// green left to the beacon. (Until issue #39's walls kept their cells these were the 256-colour
/// and truecolor look too: one green for every lit wall, which hid the seams between cells.)
pub(crate) const GLOW_STEPS: [GlowStep; GLOW_STEP_COUNT] = [
    GlowStep { chroma: 0.10, gain: 0.9, lift: 0.0 },
    GlowStep { chroma: 0.125, gain: 0.9, lift: 0.0 },
    GlowStep { chroma: 0.125, gain: 1.25, lift: 0.03 },
];

/// One step of the exit's light on walls: see [`GLOW_STEPS`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GlowStep {
    /// OKLab chroma ⁄ lightness of the glow's green.
    pub(crate) chroma: f32,
    /// The factor on the wall's own luminance.
    pub(crate) gain: f32,
    /// Luminance the exit's light adds (linear).
    pub(crate) lift: f32,
}

/// The 16-colour step (0..[`GLOW_STEP_COUNT`]) of a lit cell's `level` (1..=[`EXIT_LIGHT`]): the
/// reach in thirds, the last third nearest the exit.
#[must_use]
pub(crate) fn glow_step_16(level: u8) -> usize {
    let level = usize::from(level.clamp(1, EXIT_LIGHT) - 1);
    (level * GLOW_STEP_COUNT / usize::from(EXIT_LIGHT)).min(GLOW_STEP_COUNT - 1)
}

/// A wall of `color` (its own light: the sun's and the headlight's) lit by the exit's light at
/// `level` (0: none, the wall as it is), as 16 colours show it (one dark green, its seams and
/// corners in a line colour of their own: `palette::glow_line_16`): the glow's green at its step's
/// chroma, its luminance that of the wall's lightness times the step's gain plus its lift
/// ([`GLOW_STEPS`]).
#[must_use]
pub(crate) fn exit_lit_wall_16(color: Vec3, level: u8) -> Vec3 {
    if level == 0 {
        return color;
    }
    let step = GLOW_STEPS[glow_step_16(level)];
    // The luminance of a grey of the wall's OKLab lightness, not the wall's own: generated walls share
    // one lightness and differ by hue alone, and their luminances by up to 10 % with it, which in 256
    // colours put two like walls of one step either side of an entry's edge (a side wall (95, 135, 95)
    // beside one (95, 175, 135)), the step's look blurred by the hue the glow replaces.
    let lightness = crate::palette::oklab(color).x.max(0.0);
    glow_colour(step.chroma) * (lightness * lightness * lightness * step.gain + step.lift)
}

/// How many looks the exit's light gives a wall in truecolor and 256 colours over its reach
/// ([`glow_look`], [`exit_lit_wall`]): every seven openings of path a new one.
pub(crate) const GLOW_LOOKS: u8 = 4;

/// How much of a lit wall's own hue (OKLab (a, b)) the exit's light keeps, at its first look (the
/// edge of its reach) and its last (the exit's cell and the six before it): see [`exit_lit_wall`].
pub(crate) const GLOW_WALL_KEEP: (f32, f32) = (0.8, 0.4);

/// The exit's green a lit wall takes on (OKLab chroma relative to its lightness, along the glow's
/// hue) at its first look and its last: see [`exit_lit_wall`].
pub(crate) const GLOW_TINT: (f32, f32) = (0.06, 0.15);

/// The lightness a lit wall gains at the last look (OKLab L × (1 + this); none at the first, evenly
/// between): see [`exit_lit_wall`].
pub(crate) const GLOW_LIFT: f32 = 0.12;

/// No lit wall's chroma is more than this share of its lightness (OKLab C ⁄ L), the beacon's green's
/// being 0.18: a wall whose own hue is near the glow's is not made vivid by it.
pub(crate) const GLOW_CHROMA_MAX: f32 = 0.17;

/// The lift ([`GLOW_LIFT`]) raises no lit wall past this OKLab lightness: the beacon's green shows
/// lighter (a wall faced square on in full light, lifted, took the beacon's light mint in 256 colours).
pub(crate) const GLOW_LIGHTNESS_MAX: f32 = 0.84;

/// The look (0..[`GLOW_LOOKS`]) of a lit cell's `level` (1..=[`EXIT_LIGHT`]): the reach in
/// [`GLOW_LOOKS`] equal parts, 0 at its edge (levels 1–7, 21–27 openings from the exit), 3 nearest
/// the exit (levels 22–28: the exit's cell and the six before it).
#[must_use]
pub(crate) fn glow_look(level: u8) -> u8 {
    let level = usize::from(level.clamp(1, EXIT_LIGHT) - 1);
    (level * usize::from(GLOW_LOOKS) / usize::from(EXIT_LIGHT)).min(usize::from(GLOW_LOOKS) - 1) as u8
}

/// A wall of `color` (its own light: the sun's and the headlight's) lit by the exit's light at
/// `level` (0: none, the wall as it is), in truecolor and 256 colours (16 colours:
/// [`exit_lit_wall_16`]): **the wall's own colour tinted toward the glow's green**, more at each of
/// the [`GLOW_LOOKS`] looks toward the exit ([`glow_look`]). In OKLab the wall's (a, b) is scaled by
/// [`GLOW_WALL_KEEP`] and moved along the glow's hue by [`GLOW_TINT`] × its lightness, its
/// lightness raised by up to [`GLOW_LIFT`], its chroma at most [`GLOW_CHROMA_MAX`] of its
/// lightness. A move in (a, b) keeps two walls' difference (scaled by the keep), so neighbouring
/// cells' walls, the seams between them and a wall seen through an opening stay apart as they are
/// outside the light (issue #39: one green for every lit wall hid them), while every wall leans
/// greener, and near the exit lighter, the nearer the exit. A wall whose own hue is opposite the
/// glow's (pink, mauve) passes near grey on the way. The pipeline draws it in colour only: it
/// changes a wall's luminance, which ascii would draw as nearness.
#[must_use]
pub(crate) fn exit_lit_wall(color: Vec3, level: u8) -> Vec3 {
    if level == 0 {
        return color;
    }
    let lab = crate::palette::oklab(color.max(Vec3::ZERO));
    let along = f32::from(glow_look(level)) / f32::from(GLOW_LOOKS - 1);
    let between = |(first, last): (f32, f32)| first + (last - first) * along;
    let own = lab.x.max(0.0);
    let lightness = (own * (1.0 + GLOW_LIFT * along)).min(GLOW_LIGHTNESS_MAX.max(own));
    let mut ab =
        Vec2::new(lab.y, lab.z) * between(GLOW_WALL_KEEP) + glow_direction() * (own * between(GLOW_TINT));
    let most = GLOW_CHROMA_MAX * lightness;
    if ab.length() > most {
        ab *= most / ab.length();
    }
    linear_from_oklab(Vec3::new(lightness, ab.x, ab.y)).max(Vec3::ZERO)
}

/// The sun: a fixed directional light (world space, unit length, pointing toward the light: east by
/// north-east, level), so walls facing different ways differ a little even without fog (a faint
/// shade: [`SUN_LOW`]). Its angle, atan(1/3)
/// from east, spreads the four faces of a grid maze evenly: `n·s` is ±0.95 and ±0.32.
pub(crate) const SUN_WORLD: Vec3 = Vec3::new(0.948_683_3, 0.316_227_76, 0.0);
/// How much the sun changes a wall: from `SUN_LOW` × its headlit colour (turned away) to `SUN_HIGH` ×
/// (facing it). Just under 1, so the picture keeps its brightness; a span of 1.05×, small beside the
/// headlight's (issue #39: at 0.7–1.2 the sun's 1.7× outweighed the headlight's 1.54×, and a side wall
/// facing the sun came out lighter than a wall faced square on turned from it, so lightness told the
/// compass, not the geometry; the walls' hues now tell a corner's two walls apart).
pub(crate) const SUN_LOW: f32 = 0.95;
/// See [`SUN_LOW`].
pub(crate) const SUN_HIGH: f32 = 1.0;

/// The sun's factor for a surface whose unit normal, turned toward the eye, is `facing`, with `sun`
/// the unit direction to the sun, both in one space (view space in the pipeline: the normal through the
/// normal matrix, the sun through the view's rotation). Half-Lambert (`½ + ½ n·s`), not Lambert: faces
/// turned away from the sun still differ by how far they are turned, so each of a grid maze's four
/// wall orientations has its own shade.
#[must_use]
pub(crate) fn sun_factor(facing: Vec3, sun: Vec3) -> f32 {
    SUN_LOW + (SUN_HIGH - SUN_LOW) * (0.5 + 0.5 * facing.dot(sun)).clamp(0.0, 1.0)
}

/// The least light a wall reflects: a black wall (`0 0 0` in a course file) is drawn as a very dark
/// grey, never as the fog. Added in proportion to how dark the colour's brightest channel is, so
/// coloured walls keep their hue.
pub(crate) const MIN_WALL_ALBEDO: f32 = 0.08;

/// A wall colour (linear) lifted so it is never black: `albedo + MIN_WALL_ALBEDO · (1 − max channel)`.
#[must_use]
pub(crate) fn wall_albedo(albedo: Vec3) -> Vec3 {
    let albedo = albedo.clamp(Vec3::ZERO, Vec3::ONE);
    albedo + Vec3::splat(MIN_WALL_ALBEDO * (1.0 - albedo.max_element()))
}

/// An edge sample's colour: darker than the surface, or, on a surface too dark to darken visibly,
/// lighter, so an edge shows on every colour.
#[must_use]
pub(crate) fn edge_color(color: Vec3) -> Vec3 {
    if luminance(color) > 0.02 { color * 0.5 } else { color.lerp(Vec3::splat(0.06), 0.6) }
}

/// A seam sample's colour (a cell boundary: two walls of one line meeting, an opening's line on the
/// floor): between the surface and its [`edge_color`], so cells can be counted without the seams
/// reading as corners.
#[must_use]
pub(crate) fn seam_color(color: Vec3) -> Vec3 {
    color.lerp(edge_color(color), 0.6)
}

/// A cell line's colour in truecolor and 256 colours (the line across an opening, on the floor or the
/// ceiling sample `color`): the plane with a grey added, [`LINE_STEP`] lighter in OKLab L, so
/// the line reads as a light line on the plane at every distance, as 16 colours' light grey does, and
/// fades with the plane. Darker (a seam's colour, as until issue #39's last round) it was a dark line
/// on the dark grey floor in 256 colours, one a player did not see.
#[must_use]
pub(crate) fn line_color(color: Vec3) -> Vec3 {
    let color = if color.is_finite() { color.max(Vec3::ZERO) } else { Vec3::ZERO };
    // (a grey's OKLab L is the cube root of its luminance, and the planes are near grey; by luminance,
    // a plane tinted by the exit's light and the same untinted get one grey, so the tint keeps the
    // line's luminance as it keeps the plane's)
    let lightness = luminance(color).cbrt();
    // a grey added, not the colour scaled: the plane's tint kept, its chroma not raised with its light
    // (scaled, a floor tinted by the exit's light gave lines twice as green, which 16 colours show grey)
    let lit = color + Vec3::splat((lightness + LINE_STEP).powi(3) - lightness.powi(3));
    lit.min(Vec3::ONE)
}

/// How much lighter than its plane a cell line is ([`line_color`], OKLab L): about three and a half
/// steps of the 256-colour grey ramp (0.035 each in L at the floor's lightness), so the palette's
/// rounding on both sides leaves at least two; as far above the floor as the way's yellow-green line,
/// which its chroma keeps apart.
pub(crate) const LINE_STEP: f32 = 0.12;

/// A door jamb's colour (where a wall ends at an opening): a pale grey at least [`JAMB_STEP`] lighter
/// in OKLab L than the wall, and never darker than [`JAMB_LEAST_L`] (not white, not the beacon's
/// green), so an opening shows as a light tick apart from both walls beside it, however far: walls
/// are all about L 0.75 near and darker with distance, so the wall beside a far jamb (the face seen
/// through the opening) is darker still. At `lerp(0.6, 0.35)` a jamb on a pale wall was 0.05 in L
/// off it, one 256-colour step, and a player missed the last cell's side openings (issue #39).
#[must_use]
pub(crate) fn jamb_color(color: Vec3) -> Vec3 {
    // a grey's OKLab L is the cube root of its luminance
    let lightness = luminance(color).max(0.0).cbrt();
    let jamb = (lightness + JAMB_STEP).clamp(JAMB_LEAST_L, JAMB_MOST_L);
    Vec3::splat(jamb * jamb * jamb)
}

/// How much lighter than its wall a jamb is, at least (OKLab L; up to [`JAMB_MOST_L`]): four or five
/// steps of the 256-colour grey ramp.
pub(crate) const JAMB_STEP: f32 = 0.18;
/// The darkest a jamb is drawn (OKLab L), so a far wall's jamb stands out of the fog.
pub(crate) const JAMB_LEAST_L: f32 = 0.86;
/// The lightest a jamb is drawn (OKLab L): below white, which is the beacon's band.
pub(crate) const JAMB_MOST_L: f32 = 0.96;

/// A door jamb's colour in 16 colours: the grey of [`jamb_color`]'s luminance. There a coloured wall
/// never shows the light grey or the white (`palette::LIGHT_GREYS_16`), so a grey jamb is a light tick
/// no coloured wall is drawn in, near or far (issue #39: openings 3+ cells away could not be read).
#[must_use]
pub(crate) fn jamb_grey(color: Vec3) -> Vec3 {
    Vec3::splat(luminance(jamb_color(color)))
}

/// The line across an opening the exit's light comes through toward the eye (a lit cell's way one
/// step nearer the exit, `ExitLight::lit_through`), in truecolor and 256 colours: the light itself,
/// a saturated yellow-green (sRGB (95, 135, 0), the 256-colour cube's own entry 64, so both depths
/// show one colour), the same at any distance, whatever the floor under it. More saturated than any
/// lit wall (chroma ≤ 0.17 of L, toward the beacon's spring green) and of another hue than the
/// beacon's green and white bands; no generated wall is yellow-green (issue #39). Its lightness
/// (OKLab L 0.57) is under a wall's: a lighter line at a wall's foot made the wall look taller, or
/// its foot part of the floor (`far_wall_height`, `wall_floor`).
#[must_use]
pub(crate) fn way_light(_color: Vec3) -> Vec3 {
    Vec3::new(srgb_to_linear(95.0 / 255.0), srgb_to_linear(135.0 / 255.0), 0.0)
}

/// [`way_light`] in 16 colours: the dark yellow (xterm's 3, (205, 205, 0)), which the floor, the
/// ceiling, the glow's dark green, its lines' dark cyan, the beacon's bright green and white and the
/// other cell lines' light grey are not, and the rarest wall entry but two (a wall beyond the glow,
/// brown or olive, may show it: the 16 colours have no entry left that no wall shows).
#[must_use]
pub(crate) fn way_light_16(_color: Vec3) -> Vec3 {
    // (the yellow ramp's dark end: from 0.25 of full light up it takes the bright yellow, xterm's 11,
    // a far commoner wall entry)
    Vec3::new(0.12, 0.12, 0.0)
}

/// A chalk mark's colour on a floor sample of `color` ([`Renderer::set_chalk`]): the floor lit about
/// twice as bright and tinted pale blue ([`CHALK_TINT`]), so a mark reads as chalk on the floor (a
/// cross in the middle of a cell, where the cell lines, [`line_color`], about as light near but
/// grey, run along its sides) and fades with the floor into the distance. No channel below the
/// floor's: a mark is never darker than the floor under it.
///
/// [`Renderer::set_chalk`]: crate::Renderer::set_chalk
#[must_use]
pub(crate) fn chalk_color(color: Vec3) -> Vec3 {
    ((color * 2.2).min(Vec3::splat(0.6)).max(color) * CHALK_TINT).min(Vec3::ONE).max(color)
}

/// Chalk's tint (linear RGB factors): blue, so that a mark is not taken for one of the floor's grey
/// cell lines, which a cross's arms look like a few cells off, squashed by the angle (through the
/// lens a new player counted them as lines, issue #39); strong enough that 256 and 16 colours show
/// a blue entry, not a grey (a tint of 1.4 on blue showed grey in 256 colours). 0.9 of a grey's
/// luminance.
const CHALK_TINT: Vec3 = Vec3::new(0.6, 0.85, 2.2);

/// Brick courses: each course [`BRICK_HEIGHT`] tall, bricks [`BRICK_LENGTH`] long, every other course
/// offset by half a brick, joined by mortar [`MORTAR`] wide (maze units).
pub(crate) const BRICK_LENGTH: f32 = 1.0;
/// See [`BRICK_LENGTH`].
pub(crate) const BRICK_HEIGHT: f32 = 0.5;
/// See [`BRICK_LENGTH`].
pub(crate) const MORTAR: f32 = 0.06;
/// How dark mortar is, as a factor on the wall's colour.
const MORTAR_SHADE: f32 = 0.55;
/// How much one brick's shade differs from the next (± half of it).
const BRICK_VARIATION: f32 = 0.12;

/// The brick texture's factor on a wall's colour at wall point (`u` along the wall, `v` = height z),
/// filtered over a sample's `footprint` (maze units one sample covers there): mortar lines are
/// antialiased over the footprint and fade to their average share, and the bricks' shade differences
/// to none, as the footprint nears their period, so distant walls are an even tone instead of
/// shimmering (the texture is filtered at the sample rate, a box filter by distance).
#[must_use]
pub(crate) fn bricks(u: f32, v: f32, footprint: f32) -> f32 {
    let course = (v / BRICK_HEIGHT).floor();
    let offset = if floor_is_odd(course) { 0.5 * BRICK_LENGTH } else { 0.0 };
    let along = u / BRICK_LENGTH + offset / BRICK_LENGTH;
    let brick = along.floor();
    // Distance (maze units) to the nearest joint, across and along the courses.
    let to_bed = (v / BRICK_HEIGHT - course).min(course + 1.0 - v / BRICK_HEIGHT) * BRICK_HEIGHT;
    let to_head = (along - brick).min(brick + 1.0 - along) * BRICK_LENGTH;
    let footprint = footprint.max(1e-4);
    // A joint's coverage of the sample: a box filter of the line's edge, then, as the footprint grows
    // toward the period, the line's average share of the period.
    let joint = |distance: f32, period: f32| {
        let sharp = ((0.5 * MORTAR - distance) / footprint + 0.5).clamp(0.0, 1.0);
        let fade = (footprint / (0.5 * period)).clamp(0.0, 1.0);
        sharp + (MORTAR / period - sharp) * fade
    };
    // Either joint: the union of the two coverages.
    let mortar = 1.0 - (1.0 - joint(to_bed, BRICK_HEIGHT)) * (1.0 - joint(to_head, BRICK_LENGTH));
    // Each brick its own shade, from a hash of its row and column, fading out with distance as well.
    let hash = ((brick as i32).wrapping_mul(73_856_093) ^ (course as i32).wrapping_mul(19_349_663)) as u32;
    let shade_fade = 1.0 - (footprint / (0.5 * BRICK_HEIGHT)).clamp(0.0, 1.0);
    let tone = 1.0 + BRICK_VARIATION * ((hash % 1024) as f32 / 1023.0 - 0.5) * shade_fade;
    tone + (MORTAR_SHADE - tone) * mortar
}

/// Distance fog: the light that reaches the eye from a surface falls off with its distance as from a
/// lamp the viewer carries, `keep = 1 / (1 + (distance / half)²)` (half of it left at `half`), and
/// over the last [`FOG_FADE`] of the way to `end` the rest fades to the fog's colour, which is all
/// there is from `end` on. A wall six cells away is then much darker than the same wall one cell away
/// (issue #33: the depth you can read), and nothing pops in at the far plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fog {
    /// The colour distant things fade to (linear RGB).
    pub color: Vec3,
    /// Distance (world units) at which half the light is left.
    pub half: f32,
    /// Distance where the fog is complete (the far plane).
    pub end: f32,
}

/// The share of the way to [`Fog::end`] over which what is left of the light fades out.
pub(crate) const FOG_FADE: f32 = 0.25;

impl Fog {
    /// How much of a surface's light is left at `distance` (1 at the eye, 0 from `end` on).
    #[must_use]
    pub fn keep(&self, distance: f32) -> f32 {
        let fade = ((self.end - distance) / (FOG_FADE * self.end).max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
        let r = distance.max(0.0) / self.half.max(f32::MIN_POSITIVE);
        fade / (1.0 + r * r)
    }

    /// How much fog at `distance`: `1 − keep`, in 0..1.
    #[must_use]
    pub fn amount(&self, distance: f32) -> f32 {
        1.0 - self.keep(distance)
    }

    /// `color` seen through the fog at `distance`.
    #[must_use]
    pub fn apply(&self, color: Vec3, distance: f32) -> Vec3 {
        color.lerp(self.color, self.amount(distance))
    }
}

/// A floor or ceiling colour with a faint checker on the maze plane, so sliding and turning show.
///
/// `world` is the point on the plane (x east, y north); squares are `period` world units wide; one square
/// colour is `base`, the other `base · (1 - contrast)` (contrast 0..1, about 0.15 reads as subtle).
///
/// [`checker_filtered`] fades the squares into their mean as a sample's footprint nears their size.
#[must_use]
pub(crate) fn checker(base: Vec3, world: Vec2, period: f32, contrast: f32) -> Vec3 {
    // The square's parity in integers: `floor` and `rem_euclid` on floats are libm calls on baseline
    // x86-64, and this runs for every floor and ceiling sample.
    let cell = world / period;
    let odd = floor_is_odd(cell.x) != floor_is_odd(cell.y);
    if odd { base * (1.0 - contrast.clamp(0.0, 1.0)) } else { base }
}

/// [`checker`] seen through a sample covering `footprint` maze units: the contrast fades to nothing
/// (both squares at their mean) as the footprint grows from a tenth of a square to half of one, so the
/// far floor is even instead of a shimmer of aliased squares.
#[must_use]
pub(crate) fn checker_filtered(base: Vec3, world: Vec2, period: f32, contrast: f32, footprint: f32) -> Vec3 {
    let fade = ((footprint / period - 0.1) / 0.4).clamp(0.0, 1.0);
    let contrast = contrast.clamp(0.0, 1.0);
    let sharp = checker(base, world, period, contrast);
    sharp.lerp(base * (1.0 - 0.5 * contrast), fade)
}

/// Whether `v.floor()` is odd, in integers (exact for |v| < 2^63, which holds every float of fewer
/// integer digits; NaN counts as even, like 0). No branch: a 64-bit conversion, one comparison
/// (`floor` and `rem_euclid` on floats are libm calls on baseline x86-64).
#[inline]
fn floor_is_odd(v: f32) -> bool {
    let t = v as i64; // truncates toward zero (saturates; NaN → 0)
    t.wrapping_sub(i64::from(t as f32 > v)) & 1 == 1
}

/// The linear value of an sRGB-encoded channel (for colours read from files or the CLI).
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// The sRGB encoding of a linear channel in 0..1 (clamped; NaN → 0).
#[must_use]
#[cfg(test)]
pub(crate) fn linear_to_srgb(c: f32) -> f32 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

/// The 8-bit sRGB code of a linear channel: `round(255 · srgb(c))` with the curve evaluated in `f64`
/// (clamped to 0..1; NaN → 0), by two table reads and one comparison: what the glyph pass computes
/// with [`Srgb8Tables`] for every channel of every sample (this one-channel form is for the tests).
///
/// `threshold[k]` is the least `f32` whose code is at least `k`. The curve is monotone, so the code of
/// `c` is the number of thresholds at or below it; a 4096-bucket table gives the code at each bucket's
/// start, and as the curve rises by less than one code per bucket (its steepest slope, 255 · 12.92 at
/// the toe, is 0.8 codes per 1/4096) at most one threshold more lies inside the bucket.
#[must_use]
#[cfg(test)]
pub(crate) fn linear_to_srgb8(c: f32) -> u8 {
    Srgb8Tables::get().encode(c)
}

const SRGB8_BUCKETS: usize = 4096;

pub(crate) struct Srgb8Tables {
    /// Code at the start `b / 4096` of each bucket.
    bucket: [u8; SRGB8_BUCKETS],
    /// The least `f32` with code ≥ k, for k in 0..=255; `[256]` is NaN, which no input reaches or
    /// passes (+∞ included), so the lookup needs no branch and no saturation.
    threshold: [f32; 257],
}

static SRGB8_TABLES: std::sync::OnceLock<Srgb8Tables> = std::sync::OnceLock::new();

impl Srgb8Tables {
    /// The tables, built on first use (a few hundred bisections).
    #[inline]
    pub(crate) fn get() -> &'static Srgb8Tables {
        SRGB8_TABLES.get_or_init(Srgb8Tables::new)
    }

    /// `linear_to_srgb8` (the tests' one-channel form) with the tables in hand (hot loops fetch them once).
    #[inline]
    pub(crate) fn encode(&self, c: f32) -> u8 {
        // No branch: the saturating conversion sends NaN and c ≤ 0 to bucket 0 (code 0, and NaN fails
        // the comparison), c ≥ 1 to the last bucket, whose comparison with threshold[255] then gives 255
        // (and with threshold[256], NaN, nothing more: the sum stays within a byte).
        let start = self.bucket[((c * SRGB8_BUCKETS as f32) as u32 as usize).min(SRGB8_BUCKETS - 1)];
        start + u8::from(c >= self.threshold[usize::from(start) + 1])
    }

    /// Whether the code of `c` is at least `code` (0..=256; 256: never), by one comparison.
    #[inline]
    pub(crate) fn reaches(&self, c: f32, code: usize) -> bool {
        c >= self.threshold[code]
    }

    /// [`Srgb8Tables::encode`] of each channel (written out: `to_array().map` left a call per sample).
    #[inline(always)]
    pub(crate) fn encode3(&self, c: Vec3) -> [u8; 3] {
        [self.encode(c.x), self.encode(c.y), self.encode(c.z)]
    }

    fn new() -> Srgb8Tables {
        let code = |c: f32| -> u8 {
            let c = f64::from(c);
            let srgb = if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
            (srgb.clamp(0.0, 1.0) * 255.0).round() as u8
        };
        // Built on a process's first frame, so cheap (issue #16: ≈ 0.5 ms when it bisected): each
        // threshold starts from the curve's inverse at the code's lower half-step and walks the few
        // floats to the exact boundary; the bit patterns of 0..=1 are ordered like the values.
        let mut threshold = [f32::INFINITY; 257];
        threshold[256] = f32::NAN;
        threshold[0] = 0.0;
        for (k, t) in threshold.iter_mut().enumerate().take(256).skip(1) {
            let guess = srgb_to_linear((k as f32 - 0.5) / 255.0).clamp(0.0, 1.0);
            let mut bits = guess.to_bits();
            while usize::from(code(f32::from_bits(bits))) < k {
                bits += 1;
            }
            while bits > 0 && usize::from(code(f32::from_bits(bits - 1))) >= k {
                bits -= 1;
            }
            *t = f32::from_bits(bits);
        }
        // Each bucket's start code: the thresholds at or below the start, counted in one walk.
        let mut bucket = [0u8; SRGB8_BUCKETS];
        let mut below = 0;
        for (b, start_code) in bucket.iter_mut().enumerate() {
            let c = b as f32 / SRGB8_BUCKETS as f32;
            while below < 255 && threshold[below + 1] <= c {
                below += 1;
            }
            *start_code = below as u8;
        }
        Srgb8Tables { bucket, threshold }
    }
}

/// Relative luminance (Rec. 709 weights) of a linear colour.
#[must_use]
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headlight_is_full_face_on_and_zero_edge_on_from_either_side() {
        assert!((headlight(Vec3::Z) - 1.0).abs() < 1e-6);
        assert!((headlight(-Vec3::Z) - 1.0).abs() < 1e-6); // the back face
        assert!(headlight(Vec3::X).abs() < 1e-6); // a side wall, seen edge-on
        assert!((headlight(Vec3::new(0.6, 0.0, 0.8)) - 0.512).abs() < 1e-6); // 0.8 cubed
        assert_eq!(lit(Vec3::ONE, 0.0, 0.25), Vec3::splat(0.25));
        // A ray meeting a wall squarely, and grazing it.
        let wall = Vec3::new(0.0, 0.0, -3.0);
        assert!((slant_cosine(Vec3::Z, wall) - 1.0).abs() < 1e-6);
        assert!(slant_cosine(Vec3::X, wall).abs() < 1e-6);
    }

    #[test]
    fn fog_halves_the_light_at_half_and_is_whole_at_the_end() {
        let fog = Fog { color: Vec3::ONE, half: 4.0, end: 40.0 };
        assert_eq!(fog.amount(0.0), 0.0);
        assert!((fog.keep(4.0) - 0.5).abs() < 1e-6);
        assert!((fog.keep(8.0) - 0.2).abs() < 1e-6, "1 / (1 + 2²)");
        assert_eq!(fog.amount(40.0), 1.0);
        assert_eq!(fog.amount(90.0), 1.0);
        // The last quarter fades out what is left: at 35, 50 % of 1/(1 + 8.75²).
        assert!((fog.keep(35.0) - 0.5 / (1.0 + 8.75f32.powi(2))).abs() < 1e-6);
        assert_eq!(fog.apply(Vec3::ZERO, 4.0), Vec3::splat(0.5));
        // Nearer is never foggier.
        let amounts: Vec<f32> = (0..=100).map(|k| fog.amount(k as f32 * 0.5)).collect();
        assert!(amounts.windows(2).all(|w| w[0] <= w[1]), "{amounts:?}");
    }

    #[test]
    fn srgb8_by_table_is_the_rounded_curve() {
        let exact = |c: f32| -> u8 {
            let c = f64::from(if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) });
            let srgb = if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
            (srgb * 255.0).round() as u8
        };
        // Every 97th float in 0..=1, and the floats on both sides of every code boundary.
        let mut boundaries = 0;
        let mut previous = 0;
        for bits in (0..=1.0f32.to_bits()).step_by(97).chain([1.0f32.to_bits()]) {
            let c = f32::from_bits(bits);
            let code = linear_to_srgb8(c);
            assert_eq!(code, exact(c), "{c}");
            if code != previous {
                boundaries += 1;
                // Walk back to the exact boundary between the two codes and check both sides of it.
                let mut b = bits;
                while linear_to_srgb8(f32::from_bits(b - 1)) == code {
                    b -= 1;
                }
                for side in [b - 1, b] {
                    assert_eq!(linear_to_srgb8(f32::from_bits(side)), exact(f32::from_bits(side)));
                }
                assert!(linear_to_srgb8(f32::from_bits(b - 1)) < code);
            }
            previous = code;
        }
        assert_eq!(boundaries, 255);
        for (c, code) in [(-1.0, 0), (0.0, 0), (1.0, 255), (2.0, 255), (f32::NAN, 0), (f32::INFINITY, 255)] {
            assert_eq!(linear_to_srgb8(c), code, "{c}");
        }
    }

    #[test]
    fn checker_alternates_by_square_and_srgb_round_trips() {
        let base = Vec3::splat(0.5);
        assert_eq!(checker(base, Vec2::new(0.5, 0.5), 1.0, 0.2), base);
        assert_eq!(checker(base, Vec2::new(1.5, 0.5), 1.0, 0.2), base * 0.8);
        assert_eq!(checker(base, Vec2::new(-0.5, 0.5), 1.0, 0.2), base * 0.8);
        for v in [-3.5f32, -2.0, -1.0, -0.5, -0.0, 0.0, 0.25, 1.0, 1.5, 2.999, 1.0e7 + 1.0, -1.0e9, 1.0e18] {
            let float_way = v.floor().rem_euclid(2.0) >= 1.0;
            assert_eq!(floor_is_odd(v), float_way, "{v}");
        }
        for c in [0.0, 0.002, 0.2, 0.5, 1.0] {
            assert!((srgb_to_linear(linear_to_srgb(c)) - c).abs() < 1e-5);
        }
    }

    #[test]
    fn bricks_have_dark_joints_and_fade_to_their_mean_far_away() {
        // Near (a tiny footprint): mortar on the joints, brick in between.
        let near = 1e-3;
        assert!((bricks(0.5, 0.0, near) - MORTAR_SHADE).abs() < 0.01, "a bed joint at z = 0");
        assert!((bricks(0.0, 0.25, near) - MORTAR_SHADE).abs() < 0.01, "a head joint");
        assert!(bricks(0.5, 0.25, near) > 0.9, "mid-brick");
        assert!((bricks(0.0, 0.75, near) - bricks(0.5, 0.75, near)).abs() > 0.2, "the next course is offset");
        // Far (a footprint of a whole course or more): one even tone wherever the sample lands.
        let far = 2.0 * BRICK_HEIGHT;
        let tones: Vec<f32> =
            (0..200).map(|k| bricks(k as f32 * 0.137, k as f32 * 0.071 - 1.0, far)).collect();
        let (lo, hi) = tones.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &t| (lo.min(t), hi.max(t)));
        assert!(hi - lo < 0.02, "far bricks vary by {}", hi - lo);
        // And that tone is the near pattern's mean (the filter keeps the brightness).
        let n = 600;
        let mean: f32 = (0..n * n)
            .map(|k| bricks((k % n) as f32 / n as f32 * 40.0, (k / n) as f32 / n as f32 * 2.0 - 1.0, near))
            .sum::<f32>()
            / (n * n) as f32;
        assert!((mean - tones[0]).abs() < 0.03, "near mean {mean}, far tone {}", tones[0]);
    }

    #[test]
    fn the_checker_fades_to_its_mean_when_its_squares_shrink_below_a_sample() {
        let base = Vec3::splat(0.5);
        let (a, b) = (Vec2::new(0.5, 0.5), Vec2::new(1.5, 0.5));
        assert_eq!(checker_filtered(base, a, 1.0, 0.2, 0.01), checker(base, a, 1.0, 0.2));
        let far = |p| checker_filtered(base, p, 1.0, 0.2, 0.6);
        assert_eq!(far(a), far(b));
        assert!((far(a) - base * 0.9).abs().max_element() < 1e-6);
    }

    /// The OKLab colour an xterm-256 entry shows.
    fn entry_lab(entry: u8) -> Vec3 {
        crate::palette::oklab(Vec3::from_array(
            mazewalk_term::frame::xterm_rgb(entry).map(|v| srgb_to_linear(f32::from(v) / 255.0)),
        ))
    }

    /// A generated wall's colour as the pipeline lights it (before the exit's light and the fog):
    /// lifted off black, the sun at `sun` (0 turned away … 1 facing it), the headlight at `diffuse`.
    fn wall_lit(srgb: [u8; 3], sun: f32, diffuse: f32) -> Vec3 {
        let albedo = wall_albedo(Vec3::from_array(srgb.map(|v| srgb_to_linear(f32::from(v) / 255.0))));
        lit(albedo * (SUN_LOW + (SUN_HIGH - SUN_LOW) * sun), diffuse, 0.65)
    }

    /// OKLab `b` is toward the exit's look from `a` by a visible step in 256 colours: its (a, b) along
    /// the glow's hue more by 0.02 and at most a little darker, or lighter by 0.03 and at most a little
    /// less green.
    fn toward_glow(a: Vec3, b: Vec3) -> bool {
        let g = super::glow_direction();
        let (ga, gb) = (Vec2::new(a.y, a.z).dot(g), Vec2::new(b.y, b.z).dot(g));
        (gb >= ga + 0.02 && b.x >= a.x - 0.03) || (b.x >= a.x + 0.03 && gb >= ga - 0.02)
    }

    /// The generated wall colours lit as the pipeline lights them, at each sun side and headlight.
    fn lit_walls() -> Vec<Vec3> {
        use mazewalk_maze::generate::WALL_COLOURS;
        let mut walls = Vec::new();
        for &srgb in &WALL_COLOURS {
            for sun in [0.0, 1.0] {
                for diffuse in [0.0, 0.2, 0.6, 1.0] {
                    walls.push(wall_lit(srgb, sun, diffuse));
                }
            }
        }
        walls
    }

    /// A level of each look of the exit's light, from the edge of its reach to the exit.
    fn look_levels() -> Vec<u8> {
        let levels: Vec<u8> =
            (0..GLOW_LOOKS).map(|look| (1..=EXIT_LIGHT).find(|&l| glow_look(l) == look).unwrap()).collect();
        assert_eq!(levels.len(), usize::from(GLOW_LOOKS));
        levels
    }

    /// Issue #39: in truecolor a lit wall keeps its own colour, tinted: any two generated walls lit
    /// alike are as far apart in OKLab's (a, b) as unlit times the look's keep (within 0.005; less
    /// only where the chroma cap bites: at least 90 % are), every level of one look is one colour,
    /// each look greener (its (a, b) along the glow's hue) by at least 0.01 or lighter by 0.01 (where
    /// a cap bites: then no more is asked), never less green or darker than the one before, and no
    /// lit wall's chroma passes [`GLOW_CHROMA_MAX`] of its lightness (the beacon's is 0.18).
    #[test]
    fn a_lit_wall_keeps_its_own_colour_tinted_greener_each_look_toward_the_exit() {
        use crate::palette::oklab;
        let walls: Vec<Vec3> = lit_walls();
        let g = glow_direction();
        let green = |lab: Vec3| Vec2::new(lab.y, lab.z).dot(g);
        let levels = look_levels();
        let (mut kept, mut pairs) = (0, 0);
        for (look, &level) in levels.iter().enumerate() {
            let along = look as f32 / f32::from(GLOW_LOOKS - 1);
            let keep = GLOW_WALL_KEEP.0 + (GLOW_WALL_KEEP.1 - GLOW_WALL_KEEP.0) * along;
            let lit: Vec<Vec3> = walls.iter().map(|&w| oklab(exit_lit_wall(w, level))).collect();
            for (k, &w) in walls.iter().enumerate() {
                let lab = lit[k];
                assert!(lab.y.hypot(lab.z) <= GLOW_CHROMA_MAX * lab.x + 1e-4, "{w} level {level}: {lab}");
                for l in (1..=EXIT_LIGHT).filter(|&l| glow_look(l) == look as u8) {
                    assert!(oklab(exit_lit_wall(w, l)).distance(lab) < 1e-5, "{w}: one look, one colour");
                }
                if look > 0 {
                    let before = oklab(exit_lit_wall(w, levels[look - 1]));
                    let capped = lab.x >= GLOW_LIGHTNESS_MAX - 1e-4
                        || lab.y.hypot(lab.z) >= GLOW_CHROMA_MAX * lab.x - 1e-4;
                    let step = capped || green(lab) >= green(before) + 0.01 || lab.x >= before.x + 0.01;
                    assert!(
                        step && green(lab) >= green(before) - 1e-3 && lab.x >= before.x - 1e-4,
                        "{w} look {look}: {lab} after {before}"
                    );
                }
                for j in (k + 1..walls.len()).step_by(7) {
                    let (a, b) = (oklab(w), oklab(walls[j]));
                    // (in (a, b) only: the lift scales both lightnesses alike)
                    let unlit = Vec2::new(a.y - b.y, a.z - b.z).length() * keep;
                    let now = Vec2::new(lab.y - lit[j].y, lab.z - lit[j].z).length();
                    kept += usize::from(now >= unlit - 0.005);
                    pairs += 1;
                }
            }
        }
        // (the cap bites on walls whose own hue is near the glow's, at the last looks)
        assert!(kept * 10 >= pairs * 9, "pairs as far apart as unlit times the keep: {kept} of {pairs}");
    }

    /// Issue #39, 256 colours: of pairs of generated walls lit alike (every pair of colours, both sun
    /// sides, four angles to the headlight, fog keeping 1 or 0.6 of the light) whose unlit entries
    /// differ, the lit entries differ
    /// at least 85 % at every look near (75 % with the fog, whose darker entries are fewer; one green
    /// for all: none); at each look at least two walls in five (a third with the fog) show a visible
    /// step toward the glow from the look before (greener by 0.02 or lighter by 0.03:
    /// [`toward_glow`]), at most one in twelve the reverse (the cube's entries of a wall's tinted
    /// hue do not all lie in order), and from the edge of the reach to the exit nine in ten (three
    /// in four with the fog).
    #[test]
    fn in_256_colours_lit_walls_stay_apart_and_step_toward_the_glow() {
        use crate::palette::{Palette, ramp_entry};
        let levels = look_levels();
        let walls = lit_walls();
        for keep in [1.0, 0.6] {
            let entry = |w: Vec3, level: u8| ramp_entry(exit_lit_wall(w, level) * keep, Palette::Xterm256);
            let unlit: Vec<u8> = walls.iter().map(|&w| entry(w, 0)).collect();
            let mut looks: Vec<Vec<u8>> = Vec::new();
            for &level in &levels {
                let lit: Vec<u8> = walls.iter().map(|&w| entry(w, level)).collect();
                let (mut apart, mut pairs) = (0, 0);
                for k in 0..walls.len() {
                    for j in (k + 1..walls.len()).filter(|&j| unlit[j] != unlit[k]) {
                        apart += usize::from(lit[j] != lit[k]);
                        pairs += 1;
                    }
                }
                // (at the last look, fog keeping 0.6: 76 %; near, 87 %)
                let least = if keep == 1.0 { 80 } else { 70 };
                eprintln!("keep {keep} level {level}: apart {apart} of {pairs}");
                assert!(apart * 100 >= pairs * least, "keep {keep} level {level}: apart {apart} of {pairs}");
                looks.push(lit);
            }
            let step = |a: &[u8], b: &[u8]| {
                a.iter().zip(b).filter(|&(x, y)| toward_glow(entry_lab(*x), entry_lab(*y))).count()
            };
            let n = walls.len();
            for (look, pair) in looks.windows(2).enumerate() {
                let (forward, back) = (step(&pair[0], &pair[1]), step(&pair[1], &pair[0]));
                let why = format!("keep {keep} look {look}: {forward} of {n} forward, {back} back");
                // (near: 455, 406, 395 of 784 forward, 0, 19, 57 back; fog 0.6: 315–343, 12–53)
                eprintln!("{why}");
                assert!(
                    forward * if keep == 1.0 { 5 } else { 3 } >= n * if keep == 1.0 { 2 } else { 1 },
                    "{why}"
                );
                assert!(back * 12 <= n, "{why}");
            }
            let whole = step(&looks[0], &looks[looks.len() - 1]);
            eprintln!("keep {keep}: whole {whole} of {n}");
            // (754 of 784 near, 649 further)
            assert!(
                whole * if keep == 1.0 { 10 } else { 4 } >= n * if keep == 1.0 { 9 } else { 3 },
                "keep {keep}: {whole} of {n}"
            );
        }
    }

    /// Issue #39: no lit wall is taken for the beacon. The beacon's green (its brightest, middle
    /// column) shows a lighter entry than any lit wall at the same distance (the beacon is fogged as
    /// at half its distance), and in 16 colours lit walls show the dark green (or black)
    /// and never the beacon's bright green, which the beacon keeps.
    #[test]
    fn a_lit_wall_never_takes_the_beacons_look() {
        use crate::palette::{GLOW_16, Palette, ramp_entry};
        use mazewalk_maze::generate::WALL_COLOURS;
        let glow = crate::sprite::EXIT_GLOW;
        let bright_green = 10;
        for keep in [1.0f32, 0.8, 0.6, 0.45, 0.3, 0.2] {
            // The beacon at the same distance: half as fogged ([`Fog::keep`] at half the distance).
            let beacon_keep = 1.0 / (1.0 + (1.0 / keep - 1.0) / 4.0);
            let beacon = ramp_entry(glow * beacon_keep, Palette::Xterm256);
            assert_eq!(ramp_entry(glow * keep.max(0.5), Palette::Ansi16), bright_green, "the beacon's own");
            for &srgb in &WALL_COLOURS {
                for (sun, diffuse) in [(0.0, 0.0), (1.0, 1.0), (0.5, 0.5)] {
                    for level in 1..=EXIT_LIGHT {
                        let lit = exit_lit_wall(wall_lit(srgb, sun, diffuse), level) * keep;
                        let lit_16 = exit_lit_wall_16(wall_lit(srgb, sun, diffuse), level) * keep;
                        let shown = ramp_entry(lit, Palette::Xterm256);
                        let (b, w) = (entry_lab(beacon), entry_lab(shown));
                        let chroma = |c: Vec3| c.y.hypot(c.z);
                        assert!(
                            shown != beacon && (b.x > w.x + 0.05 || chroma(b) > chroma(w) + 0.03),
                            "{srgb:?} level {level} keep {keep}: wall {shown} {:?}, beacon {beacon} {:?}",
                            mazewalk_term::frame::xterm_rgb(shown),
                            mazewalk_term::frame::xterm_rgb(beacon)
                        );
                        let sixteen = ramp_entry(lit_16, Palette::Ansi16);
                        assert!(
                            sixteen == GLOW_16 || sixteen == 0,
                            "{srgb:?} level {level} keep {keep}: {sixteen}"
                        );
                    }
                    // and no unlit generated wall shows the glow's green in 16 colours
                    let unlit = ramp_entry(wall_lit(srgb, sun, diffuse) * keep, Palette::Ansi16);
                    assert!(unlit != GLOW_16 && unlit != bright_green, "{srgb:?} keep {keep}: {unlit}");
                }
            }
        }
    }

    /// Issue #39, 256 colours: a grey wall in the exit's light (the built-in maze's and the course
    /// files' walls may be grey; generated walls never are), lit as the pipeline lights it at both
    /// sun sides, four angles to the headlight and fog keeping 1, 0.8 or 0.6 of the light, greys
    /// from (100, 100, 100) to (220, 220, 220). At the first look it is a grey-green of chroma 0.06
    /// of its lightness, which the cube has no entry near: where that chroma is at most 0.039 it
    /// shows an entry within 0.05 in OKLab of its colour (its nearest is a grey 0.04 off; before,
    /// the cube's greens, up to 0.066 off); above 0.04 (where the hue error counts a sample) a green,
    /// its hue within 25° of the glow's. (Between the two the ramps' grid of chromaticities, whose
    /// steps move a near-grey's chroma by about 0.003, decides.) At the last look (0.15 of its lightness)
    /// every one shows a green, greener than its unlit entry by 0.02: the glow near the exit still
    /// shows on grey walls.
    #[test]
    fn in_256_colours_a_grey_wall_at_the_glows_edge_is_shown_near_its_colour() {
        use crate::palette::{Palette, hue_difference, ramp_entry};
        let g = glow_direction();
        let green = |lab: Vec3| Vec2::new(lab.y, lab.z).dot(g);
        let levels = look_levels();
        let (first, last) = (levels[0], levels[levels.len() - 1]);
        let (mut muted, mut chromatic, mut worst) = (0, 0, 0.0f32);
        for grey in (100..=220u8).step_by(10) {
            for sun in [0.0, 1.0] {
                for diffuse in [0.0, 0.2, 0.6, 1.0] {
                    for keep in [1.0, 0.8, 0.6] {
                        let wall = wall_lit([grey; 3], sun, diffuse);
                        let lit = exit_lit_wall(wall, first) * keep;
                        let lab = crate::palette::oklab(lit);
                        let shown = entry_lab(ramp_entry(lit, Palette::Xterm256));
                        let why = format!("grey {grey} sun {sun} headlight {diffuse} keep {keep}: {lab}");
                        let chroma = |c: Vec3| c.y.hypot(c.z);
                        if chroma(lab) <= 0.039 {
                            let off = shown.distance(lab);
                            worst = worst.max(off);
                            assert!(off <= 0.05, "{why}: shown {shown}, {off:.3} off");
                            muted += 1;
                        } else if chroma(lab) > 0.04 {
                            let turned = hue_difference(shown.z.atan2(shown.y), lab.z.atan2(lab.y));
                            assert!(chroma(shown) > 0.015 && turned <= 25f32.to_radians(), "{why}: {shown}");
                            chromatic += 1;
                        }
                        let near = exit_lit_wall(wall, last) * keep;
                        let (near, unlit) = (
                            entry_lab(ramp_entry(near, Palette::Xterm256)),
                            entry_lab(ramp_entry(wall * keep, Palette::Xterm256)),
                        );
                        assert!(
                            chroma(near) > 0.015 && green(near) >= green(unlit) + 0.02,
                            "{why}: near the exit {near}, unlit {unlit}"
                        );
                    }
                }
            }
        }
        eprintln!("muted {muted} (the furthest {worst:.3} off), chromatic {chromatic}");
        assert!(muted > 50 && chromatic > 50, "muted {muted}, chromatic {chromatic}");
    }
}
