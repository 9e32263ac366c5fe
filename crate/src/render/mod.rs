//! The wgpu renderer of the playground (wasm32, feature `render`).
