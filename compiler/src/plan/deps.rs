//! Stage `deps`: what each pass's result depends on besides what it reads — the frame-block
//! fields its entry points actually read (the check's reflection), the light array, the scene's
//! meshes — and which passes must run every frame. The runtime's reuse rule reads this.

use super::Depends;
use crate::abi::FrameField;
use crate::check::PassVersion;
use crate::ir::{Draw, Pass, PassKind, Pipeline, Read};
use crate::layout::BindSource;

/// Whether a frame-block field moves with the camera (`jitter` moves the projection): all
/// but the resolution, the clock and the scene's counts.
fn moves_with_camera(f: FrameField) -> bool {
    use FrameField::*;
    !matches!(f, Resolution | Time | FrameIndex | LightCount | SceneRadius)
}

pub(super) fn depends(p: &Pipeline, pass: &Pass, version: &PassVersion) -> Depends {
    let entries = || version.resolved.groups.iter().flat_map(|g| &g.entries);
    // The frame-block fields its entry points read (the check's reflection).
    let fields = &version.frame_fields;
    let has = |f: FrameField| fields.contains(&f);
    let draw = match &pass.kind {
        PassKind::Raster(r) => Some(&r.draw),
        _ => None,
    };
    Depends {
        camera: fields.iter().any(|f| moves_with_camera(*f)) || draw == Some(&Draw::Transparent),
        time: has(FrameField::Time),
        frame_index: has(FrameField::FrameIndex),
        lights: pass.per_light.is_none() && entries().any(|e| matches!(e.source, BindSource::Lights)),
        scene: draw.is_some_and(Draw::uses_scene)
            || entries().any(|e| {
                matches!(
                    e.source,
                    BindSource::Triangles
                        | BindSource::AreaLights
                        | BindSource::HitTriangles
                        | BindSource::HitMaterials
                        | BindSource::HitEmitters
                        | BindSource::HitCorners
                        | BindSource::HitMaps
                )
            })
            || pass.reads.iter().any(|r| p.resource(&r.name().value).is_some_and(|d| d.is_accel())),
        always: always(p, pass),
        frame_fields: fields.iter().copied().collect(),
    }
}

/// Why a pass runs every frame, if it must.
fn always(p: &Pipeline, pass: &Pass) -> Option<String> {
    if pass.always {
        return Some("`always: true`".into());
    }
    if p.always {
        return Some("the pipeline sets `always`".into());
    }
    // Ping-pong copies alternate each frame: a skipped writer would leave a stale copy.
    let history = |name: &str| p.resource(name).is_some_and(|r| r.history());
    if let Some(r) = pass.reads.iter().find(|r| matches!(r, Read::Prev(_))) {
        return Some(format!("reads the previous frame of `{}`", r.name().value));
    }
    pass.written()
        .find(|w| history(w))
        .map(|w| format!("writes history resource `{}`", w.value))
}
