//! Running headless (batch jobs, cron, containers): no session, hence no `XDG_RUNTIME_DIR`.
//! Mesa's device-select Vulkan layer then still tries to reach a Wayland compositor to rank the
//! GPUs, and libwayland prints `error: XDG_RUNTIME_DIR is invalid or not set in the environment.`
//! twice on a render that succeeds (docs/rendering.md "Rendering"). Without a session there is no display
//! whose GPU could be preferred, so the layer is switched off with Mesa's own `NODEVICE_SELECT`.

/// Sets `NODEVICE_SELECT=1` when `XDG_RUNTIME_DIR` is unset or not a directory and the user has
/// not chosen a value. Call first thing in `main`, before any thread starts.
pub fn quiet_device_select_without_session() {
    let has_session = std::env::var_os("XDG_RUNTIME_DIR")
        .is_some_and(|d| !d.is_empty() && std::path::Path::new(&d).is_dir());
    if !has_session && std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}
