// Per-pixel fragment lists (transparency = fragment_lists; the modern form of seed 003's
// stencil-routed A-buffer, §4.5, §5.9): every blended fragment takes a node from one pool by an
// atomic counter and links it in front of its pixel's list; a resolve pass sorts each list by
// depth and blends it back to front. `oit.heads`: per pixel, the index of the list's first node
// (NONE: empty); `oit.nodes`: the pool (its length is the fragment budget); `oit.counter`: nodes
// taken this frame and fragments dropped because the pool was full.

const NONE: u32 = 0xffffffffu;

// All words u32 (the depth's bits), so that `verify` reads the pool as integers: the end
// of a list, NONE, is no NaN.
struct OitNode {
    // rgba as four half floats (pack_color)
    color: vec2<u32>,
    // bitcast<u32> of the fragment's depth
    depth: u32,
    next: u32,
};

struct OitCounter {
    taken: atomic<u32>,
    dropped: atomic<u32>,
};

// A non-negative value as the bits of a half float (truncated: within 0.1%; clamped to the
// largest half). By hand: pack2x16float needs a capability not every adapter grants.
fn half_bits(x: f32) -> u32 {
    let b = bitcast<u32>(clamp(x, 0.0, 65504.0));
    let e = i32(b >> 23u) - 112;
    if e <= 0 {
        // A subnormal half (or zero): the mantissa with its leading 1, shifted down.
        return select(((b & 0x7fffffu) | 0x800000u) >> u32(14 - e), 0u, e < -10);
    }
    return (u32(e) << 10u) | ((b >> 13u) & 0x3ffu);
}

fn half_value(h: u32) -> f32 {
    let e = (h >> 10u) & 0x1fu;
    let m = h & 0x3ffu;
    if e == 0u {
        return f32(m) * exp2(-24.0);
    }
    return bitcast<f32>(((e + 112u) << 23u) | (m << 13u));
}

fn pack_color(c: vec4<f32>) -> vec2<u32> {
    return vec2<u32>(half_bits(c.r) | (half_bits(c.g) << 16u), half_bits(c.b) | (half_bits(c.a) << 16u));
}

fn unpack_color(p: vec2<u32>) -> vec4<f32> {
    return vec4<f32>(half_value(p.x & 0xffffu), half_value(p.x >> 16u), half_value(p.y & 0xffffu), half_value(p.y >> 16u));
}

fn pixel_index(p: vec2<u32>) -> u32 {
    return p.y * u32(frame.resolution.x) + p.x;
}
