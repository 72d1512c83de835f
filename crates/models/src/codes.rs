//! Code lists of Integer parameters that more than one model's table declares (the
//! codes of relnav-core's enums), so each list is declared once.

use relnav_fmi::variables::EnumType;

/// `frame` parameter values (the codes of [`relnav_core::frames::Frame`]).
pub static FRAME_TYPE: EnumType = EnumType {
    name: "Frame",
    items: &[
        (
            "radial_along_normal",
            1,
            "x radial outward, y along-track, z orbit normal (canonical; paper 002)",
        ),
        (
            "along_radial_antinormal",
            2,
            "x along-track, y radial outward, z minus orbit normal (paper 000)",
        ),
        (
            "along_antinormal_nadir",
            3,
            "x along-track, y minus orbit normal, z nadir (paper 003)",
        ),
    ],
};

/// `noise_model` parameter values (the codes of [`relnav_core::nav::NoiseKind`], the C
/// ABI's `relnav_noise_model`).
pub static NOISE_MODEL_TYPE: EnumType = EnumType {
    name: "NoiseModel",
    items: &[
        ("gaussian", 1, "Gaussian N(0, sigma^2)"),
        (
            "mixture",
            2,
            "Contaminated Gaussian (1 - zeta) N(0, sigma^2) + zeta N(0, (scale sigma)^2) (paper 003)",
        ),
        ("student_t", 3, "Student-t sigma t_dof"),
    ],
};

#[cfg(test)]
mod tests {
    use super::*;
    use relnav_core::frames::Frame;
    use relnav_core::nav::NoiseKind;

    /// The lists carry the library's codes (and, for the noise models, its names).
    #[test]
    fn code_lists_match_library_codes() {
        let codes: Vec<i32> = FRAME_TYPE.items.iter().map(|it| it.1).collect();
        let lib: Vec<i32> = Frame::ALL.iter().map(|f| f.code()).collect();
        assert_eq!(codes, lib);
        let names: Vec<(i32, &str)> = NOISE_MODEL_TYPE
            .items
            .iter()
            .map(|(n, v, _)| (*v, *n))
            .collect();
        let lib: Vec<(i32, &str)> = NoiseKind::ALL
            .iter()
            .map(|k| (*k as i32, k.name()))
            .collect();
        assert_eq!(names, lib);
    }
}
