//! The shared library of `relnav.fmu`: every FMI 2.0 co-simulation function, exported
//! unprefixed by relnav-fmi's feature `fmi-exports` for [`relnav_fmi::relnav::RelnavFmu`],
//! and the C ABI of the `relnav` crate beside them (`relnav_*`), as in `librelnav.so`.
//! `relnav-fmu` packs it as `binaries/linux64/relnav.so`.

use relnav as _;
use relnav_fmi as _;
