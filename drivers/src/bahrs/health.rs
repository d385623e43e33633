//! 2-bit signal health (BAHRS protocol 2.0, section 2.4) and the per-message health words of
//! 0x01 and 0x02 (sections 3.1 and 3.2).

use serde::Serialize;

/// Health of one signal, from its 2-bit field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Health {
    /// 0b00: signal unavailable.
    Unavailable,
    /// 0b01: available and safe (fault detection active, no alarm or a successful isolation).
    Safe,
    /// 0b10: available but possibly misleading (the unit declares an integrity risk).
    IntegrityRisk,
    /// 0b11: not defined by the document; kept distinct so that it is never taken as safe.
    Undefined,
}

impl Health {
    /// Decodes the two low bits of `bits`.
    #[inline]
    pub const fn from_bits(bits: u16) -> Self {
        match bits & 0b11 {
            0b00 => Health::Unavailable,
            0b01 => Health::Safe,
            0b10 => Health::IntegrityRisk,
            _ => Health::Undefined,
        }
    }

    /// The 2-bit code.
    #[inline]
    pub const fn bits(self) -> u16 {
        match self {
            Health::Unavailable => 0b00,
            Health::Safe => 0b01,
            Health::IntegrityRisk => 0b10,
            Health::Undefined => 0b11,
        }
    }

    /// Only "safe" lets a signal take part in a comparison or a solution.
    #[inline]
    pub const fn is_safe(self) -> bool {
        matches!(self, Health::Safe)
    }
}

/// Health word of the inertial message 0x01: specific force X/Y/Z in bits 0-5, angular rate X/Y/Z
/// in bits 6-11, bits 12-15 reserved (kept, never interpreted).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
pub struct InertialHealth(pub u16);

impl InertialHealth {
    /// Health of the specific force on body axis `axis` (0 = X, 1 = Y, 2 = Z).
    #[inline]
    pub const fn specific_force(self, axis: usize) -> Health {
        Health::from_bits(self.0 >> (2 * (axis % 3)))
    }

    /// Health of the angular rate on body axis `axis` (0 = X, 1 = Y, 2 = Z).
    #[inline]
    pub const fn angular_rate(self, axis: usize) -> Health {
        Health::from_bits(self.0 >> (6 + 2 * (axis % 3)))
    }

    /// The reserved bits 12-15 as sent.
    #[inline]
    pub const fn reserved(self) -> u16 {
        self.0 >> 12
    }

    /// Builds the word from per-signal health (reserved bits zero).
    pub const fn new(specific_force: [Health; 3], angular_rate: [Health; 3]) -> Self {
        Self(
            specific_force[0].bits()
                | specific_force[1].bits() << 2
                | specific_force[2].bits() << 4
                | angular_rate[0].bits() << 6
                | angular_rate[1].bits() << 8
                | angular_rate[2].bits() << 10,
        )
    }
}

/// Health word of the navigation message 0x02: pressure height bits 0-1, velocity downwards 2-3,
/// roll 4-5, pitch 6-7, magnetic heading 8-9, bits 10-15 reserved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
pub struct NavigationHealth(pub u16);

impl NavigationHealth {
    /// Health of the pressure height.
    #[inline]
    pub const fn pressure_height(self) -> Health {
        Health::from_bits(self.0)
    }
    /// Health of the downward velocity.
    #[inline]
    pub const fn velocity_down(self) -> Health {
        Health::from_bits(self.0 >> 2)
    }
    /// Health of the roll angle.
    #[inline]
    pub const fn roll(self) -> Health {
        Health::from_bits(self.0 >> 4)
    }
    /// Health of the pitch angle.
    #[inline]
    pub const fn pitch(self) -> Health {
        Health::from_bits(self.0 >> 6)
    }
    /// Health of the magnetic heading.
    #[inline]
    pub const fn heading(self) -> Health {
        Health::from_bits(self.0 >> 8)
    }
    /// The reserved bits 10-15 as sent.
    #[inline]
    pub const fn reserved(self) -> u16 {
        self.0 >> 10
    }

    /// Builds the word from per-signal health (reserved bits zero).
    pub const fn new(
        pressure_height: Health,
        velocity_down: Health,
        roll: Health,
        pitch: Health,
        heading: Health,
    ) -> Self {
        Self(
            pressure_height.bits()
                | velocity_down.bits() << 2
                | roll.bits() << 4
                | pitch.bits() << 6
                | heading.bits() << 8,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_bit_codes_of_section_2_4() {
        assert_eq!(Health::from_bits(0b00), Health::Unavailable);
        assert_eq!(Health::from_bits(0b01), Health::Safe);
        assert_eq!(Health::from_bits(0b10), Health::IntegrityRisk);
        assert_eq!(Health::from_bits(0b11), Health::Undefined);
        assert!(!Health::Undefined.is_safe());
    }

    #[test]
    fn only_code_01_is_safe() {
        // Section 2.4: 01 is "available and safe"; 00 unavailable, 10 integrity risk, and the
        // undefined 11 are not.
        assert!(Health::from_bits(0b01).is_safe());
        for bits in [0b00, 0b10, 0b11] {
            assert!(!Health::from_bits(bits).is_safe(), "{bits:#04b}");
        }
    }

    #[test]
    fn inertial_word_by_hand() {
        // 0b1111_10_01_00_11_10_01 = 0xF939: fx safe, fy risk, fz undefined, wx unavailable,
        // wy safe, wz risk, reserved 0xF.
        let h = InertialHealth(0b1111_1001_0011_1001);
        assert_eq!(h.specific_force(0), Health::Safe);
        assert_eq!(h.specific_force(1), Health::IntegrityRisk);
        assert_eq!(h.specific_force(2), Health::Undefined);
        assert_eq!(h.angular_rate(0), Health::Unavailable);
        assert_eq!(h.angular_rate(1), Health::Safe);
        assert_eq!(h.angular_rate(2), Health::IntegrityRisk);
        assert_eq!(h.reserved(), 0xF);
        let rebuilt = InertialHealth::new(
            [Health::Safe, Health::IntegrityRisk, Health::Undefined],
            [Health::Unavailable, Health::Safe, Health::IntegrityRisk],
        );
        assert_eq!(rebuilt.0, 0b1001_0011_1001);
    }

    #[test]
    fn navigation_word_by_hand() {
        // heading risk (10), pitch safe (01), roll safe (01), vd unavailable (00), height safe (01),
        // reserved bits 10-15 = 0b100001: 0b100001_10_01_01_00_01 = 0x8651.
        let h = NavigationHealth(0x8651);
        assert_eq!(h.pressure_height(), Health::Safe);
        assert_eq!(h.velocity_down(), Health::Unavailable);
        assert_eq!(h.roll(), Health::Safe);
        assert_eq!(h.pitch(), Health::Safe);
        assert_eq!(h.heading(), Health::IntegrityRisk);
        assert_eq!(h.reserved(), 0b10_0001);
        // A second word where the unavailable code (00) sits elsewhere, so that every field is
        // told apart by its own bits: heading safe (01), pitch unavailable (00), roll undefined
        // (11), vd risk (10), height unavailable (00): 0b01_00_11_10_00 = 0x138.
        let h = NavigationHealth(0x138);
        assert_eq!(h.pressure_height(), Health::Unavailable);
        assert_eq!(h.velocity_down(), Health::IntegrityRisk);
        assert_eq!(h.roll(), Health::Undefined);
        assert_eq!(h.pitch(), Health::Unavailable);
        assert_eq!(h.heading(), Health::Safe);
        assert_eq!(h.reserved(), 0);
        let rebuilt = NavigationHealth::new(
            Health::Unavailable,
            Health::IntegrityRisk,
            Health::Undefined,
            Health::Unavailable,
            Health::Safe,
        );
        assert_eq!(rebuilt.0, 0x138);
    }
}
