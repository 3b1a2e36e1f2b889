//! Keeps Mesa's "XDG_RUNTIME_DIR is invalid or not set" lines away from the user.
//!
//! Creating a Vulkan instance with Mesa's drivers (lavapipe included) makes libwayland-client
//! look for a Wayland display, and it prints that error to stderr when `XDG_RUNTIME_DIR` is
//! unset or not an absolute path, as on servers, in containers and under `sudo`. ggx renders
//! headless and never needs a display, so where the variable is missing or invalid it is
//! pointed at the temporary directory (the display is then simply not found, silently).

use std::path::Path;

/// Sets `XDG_RUNTIME_DIR` to the temporary directory when it is unset or not absolute.
///
/// Must be called before any other thread is started (see the safety note).
#[allow(unsafe_code)]
pub fn ensure_valid() {
    let valid = std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|dir| Path::new(&dir).is_absolute());
    if !valid {
        // SAFETY: the workspace's one exception to `unsafe_code = "deny"`. `set_var` is unsafe
        // because another thread could read the environment at the same time; `main` calls
        // this after parsing the arguments (clap starts no thread) and before anything else,
        // when the process has a single thread.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir()) }
    }
}
