//! afl target `search`: see `avs_fuzz::search`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::search(data));
}
