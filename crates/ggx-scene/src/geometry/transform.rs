//! The optional shape transform `{ translate, rotate, scale }`.

use glam::{Affine3A, Quat, Vec3};

use crate::check::Interval;
use crate::error::{SceneError, Source};
use crate::raw::RawTransform;

/// `M = T * Rz * Ry * Rx * S`: scale first, then rotate about x, then y, then z (angles in
/// degrees, right-handed: counter-clockwise looking down the axis), then translate.
pub(crate) fn build_transform(src: Source<'_>, raw: Option<&RawTransform>, path: &str) -> Result<Affine3A, SceneError> {
    let Some(raw) = raw else { return Ok(Affine3A::IDENTITY) };
    let field = |key: &str| format!("{path}.transform.{key}");
    let translate =
        raw.translate.as_ref().map_or(Ok([0.0; 3]), |t| src.array(t, &field("translate"), Interval::ANY))?;
    let [rx, ry, rz] = raw.rotate.as_ref().map_or(Ok([0.0; 3]), |r| src.array(r, &field("rotate"), Interval::ANY))?;
    let scale = match &raw.scale {
        None => [1.0; 3],
        Some(s) => {
            src.components(s.span(), s.get_ref().written(), &field("scale"), Interval::above(0.0))?;
            s.get_ref().components()
        }
    };
    let rotation = Quat::from_rotation_z(rz.to_radians())
        * Quat::from_rotation_y(ry.to_radians())
        * Quat::from_rotation_x(rx.to_radians());
    Ok(Affine3A::from_scale_rotation_translation(Vec3::from(scale), rotation, Vec3::from(translate)))
}
