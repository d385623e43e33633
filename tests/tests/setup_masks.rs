//! The VN-200 set-up of `vigil run` asks for the outputs the simulated VN-200 sends, so what the
//! simulator exercises is what a configured device delivers.

#[test]
fn vn200_masks_are_what_the_simulated_vn200_sends() {
    assert_eq!(
        vigil_service::runtime::setup::VN200_MASKS,
        vigil_sim::device::vn200::default_masks()
    );
}
