//! The shared library of `relnav_guidance.fmu`: every FMI 2.0 co-simulation function,
//! exported unprefixed, for [`relnav_fmi::guidance::GuidanceFmu`] (the hold-point guidance law; the model and its variable
//! table live in relnav-fmi). Built by `fmu/build.sh` in its own cargo invocation, so that
//! relnav-fmi is linked without its feature `fmi-exports` (relnav.fmu's own `fmi2*`
//! symbols) and without `hinf`; `relnav-fmu --all` packs it as
//! `binaries/linux64/relnav_guidance.so`.

relnav_fmi::export_fmi2!(relnav_fmi::guidance::GuidanceFmu);
