//! The navigator's saved state (`docs/state-format.md`): the configuration section (the
//! parameter table's saved settings), the navigator's own fields and the filter's.

use super::{FilterKind, NavError, Navigator};
use crate::estimators::{Estimator, UpdateInfo};
use crate::numerics::state::{
    self, crc32, refuse, Persist, Reader, StateError, Writer, ESTIMATOR_MAGIC, KINDS,
};

impl Navigator {
    /// The payload of a saved state: configuration section, navigator section, filter
    /// section (`docs/state-format.md`). The destructuring names every field: a new one
    /// does not compile until it is saved here or marked as configuration or cache.
    fn write_state(&self, w: &mut Writer<'_>) {
        let Self {
            cfg,
            // configuration: rebuilt from `cfg` by the restoring navigator
            dynamics: _,
            t,
            sensor: _,
            kalman_sensor: _,
            noise: _,
            scales: _,
            filter,
            // a cache of the discrete model per step size, recomputed from `cfg` (same bits)
            step_cache: _,
            // a cache of the elliptic model's Kepler anchor (no result depends on it)
            kepler: _,
            // configuration (the rates of `cfg` in the canonical frame)
            q_rates: _,
            last_update,
            // the added sensors are the caller's configuration, their reports diagnostics
            // (cleared by a restore)
            sensors: _,
            reports: _,
            pending: _,
            // configuration (from `cfg`), and the last step's diagnostics (cleared by a
            // restore)
            declared: _,
            step_nis: _,
            step_acceptance: _,
            failed,
        } = self;
        w.tag(b"CONF");
        cfg.write_settings(w);
        w.tag(b"NAVG");
        w.bool(*failed);
        w.f64(*t);
        // always the same size: zeros in place of an absent last update
        let u = last_update.unwrap_or_default();
        w.bool(last_update.is_some());
        w.matrix(&u.innovation);
        w.f64(u.nis);
        w.bool(u.azimuth_used);
        filter.save_state(w);
    }

    /// The identity block of a saved state's header: filter code (i32 LE), configuration
    /// fingerprint (u32 LE, [`NavConfig::fingerprint`]).
    fn state_ident(&self) -> [u8; 8] {
        let mut id = [0u8; 8];
        id[..4].copy_from_slice(&(self.cfg.filter as i32).to_le_bytes());
        id[4..].copy_from_slice(&self.cfg.fingerprint().to_le_bytes());
        id
    }

    /// Size in bytes of [`Navigator::save_state`]'s output (counted, nothing allocated). It
    /// depends on the configuration only (a particle filter's grows with `particles`), not
    /// on the history: one buffer of this size holds every later state.
    pub fn state_len(&self) -> usize {
        state::sealed_len(STATE_IDENT_LEN, |w| self.write_state(w))
    }

    /// Append the complete state to `out` as explicit, versioned bytes
    /// (`docs/state-format.md`): a header (magic `RELNAVES`, [`STATE_FORMAT_VERSION`],
    /// filter code, configuration fingerprint, payload length, CRC-32) and a payload with
    /// the configuration, the navigator's own state (failure flag, last-update
    /// diagnostics) and the filter's (particles, weights and generator state, the AQUKF
    /// window, the H-infinity matrices, ...). [`Navigator::restore_state`] on a navigator
    /// of the same configuration — this one or another, in this process or another —
    /// continues bit for bit as this one would.
    #[cfg(feature = "std")]
    pub fn save_state(&self, out: &mut Vec<u8>) {
        let ident = self.state_ident();
        state::seal(out, ESTIMATOR_MAGIC, STATE_FORMAT_VERSION, &ident, |w| {
            self.write_state(w)
        });
    }

    /// [`Navigator::save_state`] into the start of `out` (no heap): the state's length, or
    /// an [`NavErrorKind::InvalidArgument`] error when `out` is shorter than
    /// [`Navigator::state_len`].
    pub fn save_state_into(&self, out: &mut [u8]) -> Result<usize, NavError> {
        let ident = self.state_ident();
        state::seal_into(out, ESTIMATOR_MAGIC, STATE_FORMAT_VERSION, &ident, |w| {
            self.write_state(w)
        })
        .ok_or_else(|| NavError::invalid("the buffer is shorter than the state (state_len)"))
    }

    /// Restore a state saved by [`Navigator::save_state`]. Refused with
    /// [`NavErrorKind::InvalidState`] and a reason when the bytes are truncated or
    /// corrupted (length, CRC-32), of another format version or kind, or saved for another
    /// configuration (the message names the first setting that differs); a malformed field
    /// (a permutation that is none, an index out of range, a non-finite estimate) is
    /// refused too. Transactional: on error nothing changes.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), NavError> {
        let o = state::open(
            bytes,
            ESTIMATOR_MAGIC,
            STATE_FORMAT_VERSION,
            STATE_IDENT_LEN,
            "a relnav estimator state",
            &KINDS,
        )?;
        let mut id = Reader::new(o.ident);
        let code = id.i32("filter code")?;
        let fingerprint = id.u32("configuration fingerprint")?;
        if code != self.cfg.filter as i32 {
            let name = FilterKind::from_code(code).map_or("unknown", FilterKind::name);
            return Err(refuse(crate::msg!(
                "the state is for filter {code} ({name}), this estimator runs filter {} ({})",
                self.cfg.filter as i32,
                self.cfg.filter.name()
            ))
            .into());
        }
        let mut r = Reader::new(o.payload);
        r.tag(b"CONF")?;
        let conf_at = r.position();
        let mine = self.cfg.settings_count();
        let n = r.u32("number of settings")? as usize;
        if n != mine {
            return Err(refuse(crate::msg!(
                "the state records {n} settings, this build has {mine}"
            ))
            .into());
        }
        let mut differs: Option<StateError> = None;
        self.cfg.visit_settings(|p, i, v| {
            if differs.is_some() {
                return;
            }
            match r.u64(p.name) {
                Err(e) => differs = Some(e),
                Ok(b) if b != v.bits() => {
                    #[cfg(feature = "std")]
                    let m = crate::msg!(
                        "the state was saved for another configuration: {} = {} in the \
                         state, {v} in this estimator",
                        p.setting_name(i),
                        v.with_bits(b)
                    );
                    #[cfg(not(feature = "std"))]
                    let m = crate::message::Message::concat(&[
                        "the state was saved for another configuration: ",
                        p.name,
                        " differs",
                    ]);
                    let _ = i;
                    differs = Some(refuse(m));
                }
                Ok(_) => {}
            }
        });
        if let Some(e) = differs {
            return Err(e.into());
        }
        let conf = o.payload.get(conf_at..r.position()).unwrap_or_default();
        if crc32(conf) != fingerprint || fingerprint != self.cfg.fingerprint() {
            return Err(refuse(crate::msg!(
                "configuration fingerprint {fingerprint:08x} of the header does not match the \
                 configuration it carries ({:08x})",
                crc32(conf)
            ))
            .into());
        }
        r.tag(b"NAVG")?;
        let failed = r.bool("failure flag")?;
        let t = r.f64("step start time")?;
        if !t.is_finite() {
            return Err(refuse("the state's step start time is not finite").into());
        }
        let present = r.bool("last-update flag")?;
        let u = UpdateInfo {
            innovation: r.matrix("last innovation")?,
            nis: r.f64("last NIS")?,
            azimuth_used: r.bool("last azimuth-used flag")?,
        };
        let last_update = present.then_some(u);
        let mut filter = self.filter.clone();
        filter.load_state(&mut r)?;
        r.finish()?;
        // a crafted state behind a valid checksum can carry fields a filter reads without
        // a finiteness check (a particle filter's weighted mean): the estimate handed out
        // must be numbers (fuzz finding, `tests/robustness.rs`). The covariance is not
        // checked: a reachable state may hold an infinite one (particles spread beyond
        // 1e154 m by absurd thrust), and it must restore.
        if !filter.state().iter().all(|v| v.is_finite()) {
            return Err(refuse(
                "the state's estimate is not finite (a crafted or corrupted state behind a \
                 valid checksum)",
            )
            .into());
        }
        // commit: nothing below can fail
        self.filter = filter;
        self.last_update = last_update;
        self.reports.iter_mut().for_each(|r| *r = None);
        self.step_nis = [f64::NAN; 4];
        self.step_acceptance = f64::NAN;
        self.failed = failed;
        self.t = t;
        Ok(())
    }
}

/// Format version of [`Navigator::save_state`]'s bytes. Bump it whenever the layout
/// changes (a field added to a filter's `Persist`, a new setting); a state of another
/// version is refused, never misread.
pub const STATE_FORMAT_VERSION: u32 = 6;

/// Length of the identity block of an estimator state's header (filter code, fingerprint).
const STATE_IDENT_LEN: usize = 8;
