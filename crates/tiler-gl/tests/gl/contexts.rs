//! Several contexts sharing objects (`create_context`, `make_current`, `destroy_context`):
//! each keeps its own GL state, and drawing on two of them interleaved gives what one context
//! gives when it changes its state explicitly at each switch.

use super::common::*;
use tiler::BlendFactor;
use tiler_gl::*;

const SIZE: u32 = 16;
/// The texture (and framebuffer) one context renders into.
const TARGET: u32 = 10;

fn solid_program(gl: &mut Context, id: u32, rgba: [f32; 4]) {
    c(gl, Call::CreateProgram { id, program: ProgramKind::Solid.into() });
    c(gl, Call::UseProgram { id });
    set_color(gl, rgba);
}

/// The objects both ways share: two quads, two solid programs (red on the window, green into
/// the texture) and the texture's framebuffer.
fn objects(gl: &mut Context) {
    c(gl, Call::CreateBuffer { id: 1, data: Bytes::from_slice(&quad(-0.75, -0.75, 0.25, 0.25, 0.0)) });
    c(gl, Call::CreateBuffer { id: 2, data: Bytes::from_slice(&quad(-0.5, -0.5, 1.0, 1.0, 0.0)) });
    solid_program(gl, 2, [0.0, 1.0, 0.0, 0.5]);
    solid_program(gl, 1, [1.0, 0.0, 0.0, 0.5]);
    c(
        gl,
        Call::CreateTexture {
            id: TARGET,
            width: 8,
            height: 8,
            format: TextureFormat::Rgba8,
            data: None,
            transient: false,
        },
    );
    c(gl, Call::CreateFramebuffer { id: TARGET });
    c(
        gl,
        Call::FramebufferTexture {
            framebuffer: TARGET,
            attachment: AttachmentPoint::Color0,
            texture: TARGET,
            samples: 1,
        },
    );
}

/// The window context's state: program 1, buffer 1, blending, a blue clear colour.
fn window_state() -> Vec<Call> {
    vec![
        Call::BindFramebuffer { target: FramebufferTarget::Framebuffer, framebuffer: 0 },
        Call::Viewport { x: 0, y: 0, width: SIZE, height: SIZE },
        Call::UseProgram { id: 1 },
        Call::Enable { cap: Capability::Blend },
        Call::BlendFunc {
            src: BlendFactor::SrcAlpha,
            dst: BlendFactor::OneMinusSrcAlpha,
            src_alpha: None,
            dst_alpha: None,
        },
        Call::ClearColor { rgba: [0.0, 0.0, 1.0, 1.0] },
    ]
}

/// The offscreen context's state: the texture's framebuffer, an 8×8 viewport, program 2,
/// buffer 2, no blending, a yellow clear colour.
fn offscreen_state() -> Vec<Call> {
    vec![
        Call::BindFramebuffer { target: FramebufferTarget::Framebuffer, framebuffer: TARGET },
        Call::Viewport { x: 0, y: 0, width: 8, height: 8 },
        Call::UseProgram { id: 2 },
        Call::Disable { cap: Capability::Blend },
        Call::ClearColor { rgba: [1.0, 1.0, 0.0, 1.0] },
    ]
}

fn run(gl: &mut Context, calls: Vec<Call>) {
    for call in calls {
        c(gl, call);
    }
}

/// The drawing: the window clears and draws, the texture clears and draws, the window draws
/// again, the texture draws again; `switch(gl, to_window)` gets each side's state ready
/// (and is called once before each side's first call, the attributes included).
fn drawing(gl: &mut Context, mut switch: impl FnMut(&mut Context, bool)) -> (Vec<u8>, Vec<u8>) {
    switch(gl, true);
    clear_all(gl);
    draw(gl, 6);
    switch(gl, false);
    clear_all(gl);
    draw(gl, 6);
    switch(gl, true);
    c(gl, Call::Uniform { name: "color".into(), value: UniformValue::Vec4([1.0, 1.0, 1.0, 0.25]) });
    draw(gl, 6);
    switch(gl, false);
    draw(gl, 3);
    switch(gl, true);
    swap(gl);
    let report = gl.end().unwrap();
    assert!(report.frames.len() == 1);
    let texture = gl.device().read_rgba8(gl.texture_image(TARGET).unwrap()).unwrap();
    (gl.surface_rgba8(), texture)
}

#[test]
fn two_contexts_drawing_interleaved_match_one_context_changing_its_state() {
    // One context: every switch sets the whole state of the side it switches to.
    let mut one = context(SIZE, SIZE);
    objects(&mut one);
    let explicit = drawing(&mut one, |gl, window| {
        run(gl, if window { window_state() } else { offscreen_state() });
        attribute_from(gl, if window { 1 } else { 2 });
    });

    // Two contexts: each sets its state once; the switches are `make_current`.
    let mut two = context(SIZE, SIZE);
    objects(&mut two);
    run(&mut two, window_state());
    attribute_from(&mut two, 1);
    c(&mut two, Call::CreateContext { id: 7 });
    c(&mut two, Call::MakeCurrent { id: 7 });
    run(&mut two, offscreen_state());
    attribute_from(&mut two, 2);
    let kept = drawing(&mut two, |gl, window| {
        c(gl, Call::MakeCurrent { id: if window { 0 } else { 7 } });
    });

    assert!(explicit == kept, "two contexts drew otherwise than one changing its state");
    // The drawing did something on both sides: red-and-white over blue on the window, green
    // over yellow in the texture.
    let (window, texture) = kept;
    assert_eq!(pixel(&window, SIZE, 0, 0), [0, 0, 255, 255]);
    assert_ne!(pixel(&window, SIZE, 5, SIZE - 5), [0, 0, 255, 255]);
    assert_eq!(pixel(&texture, 8, 0, 7), [255, 255, 0, 255]);
    assert_eq!(pixel(&texture, 8, 7, 0), [0, 255, 0, 128]);
}

#[test]
fn a_switch_ends_the_pass_only_when_the_draw_framebuffer_changes() {
    // Two contexts both drawing to the window: one pass; a switch to a context drawing into a
    // texture ends it, as binding that framebuffer would.
    let mut gl = context(SIZE, SIZE);
    objects(&mut gl);
    run(&mut gl, window_state());
    attribute_from(&mut gl, 1);
    c(&mut gl, Call::CreateContext { id: 1 });
    c(&mut gl, Call::CreateContext { id: 2 });
    c(&mut gl, Call::MakeCurrent { id: 1 });
    attribute_from(&mut gl, 1);
    c(&mut gl, Call::UseProgram { id: 1 });
    c(&mut gl, Call::MakeCurrent { id: 2 });
    run(&mut gl, offscreen_state());
    attribute_from(&mut gl, 2);
    c(&mut gl, Call::MakeCurrent { id: 0 });
    clear_all(&mut gl);
    draw(&mut gl, 6);
    c(&mut gl, Call::MakeCurrent { id: 1 });
    draw(&mut gl, 6);
    c(&mut gl, Call::MakeCurrent { id: 0 });
    draw(&mut gl, 6);
    c(&mut gl, Call::MakeCurrent { id: 2 });
    clear_all(&mut gl);
    draw(&mut gl, 6);
    c(&mut gl, Call::MakeCurrent { id: 0 });
    swap(&mut gl);
    let report = gl.end().unwrap();
    let passes = passes(&report);
    let shape: Vec<_> = passes.iter().map(|p| (p.framebuffer, p.draws.len())).collect();
    assert_eq!(shape, [(0, 3), (TARGET, 1)]);
}

#[test]
fn objects_are_shared_and_deleting_one_unbinds_it_everywhere() {
    let mut gl = context(SIZE, SIZE);
    objects(&mut gl);
    run(&mut gl, window_state());
    attribute_from(&mut gl, 1);
    c(&mut gl, Call::CreateContext { id: 1 });
    c(&mut gl, Call::MakeCurrent { id: 1 });
    // Context 0 uses program 1; deleting it here keeps it until 0 stops using it.
    c(&mut gl, Call::DeleteProgram { id: 1 });
    c(&mut gl, Call::BindFramebuffer { target: FramebufferTarget::Framebuffer, framebuffer: TARGET });
    // Deleting the buffer context 0's attribute reads detaches it there too: its draw is an
    // error naming the attribute, not a read of retired storage.
    c(&mut gl, Call::DeleteBuffer { id: 1 });
    c(&mut gl, Call::DeleteFramebuffer { id: TARGET });
    c(&mut gl, Call::MakeCurrent { id: 0 });
    let error = gl.call(Call::DrawArrays { mode: Mode::Triangles, first: 0, count: 6 }).unwrap_err();
    assert!(error.message.contains("attribute 0"), "{error}");
    attribute_from(&mut gl, 2);
    draw(&mut gl, 6);
    // Program 1 goes when context 0 uses another.
    c(&mut gl, Call::UseProgram { id: 2 });
    let error = gl.call(Call::UseProgram { id: 1 }).unwrap_err();
    assert!(error.message.contains("program 1 does not exist"), "{error}");
}

#[test]
fn contexts_are_made_switched_and_destroyed_by_id_with_clear_errors() {
    let mut gl = context(SIZE, SIZE);
    let refuse = |gl: &mut Context, call: Call, says: &str| {
        let error = gl.call(call).unwrap_err();
        assert!(error.message.contains(says), "{error}");
    };
    refuse(&mut gl, Call::MakeCurrent { id: 3 }, "context 3 does not exist");
    refuse(&mut gl, Call::CreateContext { id: 0 }, "context 0 already exists");
    c(&mut gl, Call::CreateContext { id: 3 });
    refuse(&mut gl, Call::CreateContext { id: 3 }, "context 3 already exists");
    c(&mut gl, Call::MakeCurrent { id: 3 });
    refuse(&mut gl, Call::DestroyContext { id: 3 }, "context 3 is current");
    // The advisor's restore_state puts back a state in the context it was saved in only.
    let saved = gl.saved_state();
    c(&mut gl, Call::MakeCurrent { id: 0 });
    refuse(&mut gl, Call::RestoreState { state: saved.clone() }, "context 3's, but context 0 is current");
    c(&mut gl, Call::MakeCurrent { id: 3 });
    c(&mut gl, Call::RestoreState { state: saved });
    // A new context's viewport is the window's; a vertex array bound in a destroyed context
    // can still be deleted.
    c(&mut gl, Call::CreateVertexArray { id: 5 });
    c(&mut gl, Call::BindVertexArray { id: 5 });
    c(&mut gl, Call::MakeCurrent { id: 0 });
    c(&mut gl, Call::DestroyContext { id: 3 });
    refuse(&mut gl, Call::MakeCurrent { id: 3 }, "context 3 does not exist");
    c(&mut gl, Call::DeleteVertexArray { id: 5 });
    // Context 0 can go too, once another is current.
    c(&mut gl, Call::CreateContext { id: 4 });
    c(&mut gl, Call::MakeCurrent { id: 4 });
    c(&mut gl, Call::DestroyContext { id: 0 });
    clear_all(&mut gl);
    swap(&mut gl);
}

#[test]
fn a_recording_with_two_contexts_replays_from_json_to_the_same_pictures() {
    let mut gl = Context::new_recording(config(SIZE, SIZE)).unwrap();
    objects(&mut gl);
    run(&mut gl, window_state());
    attribute_from(&mut gl, 1);
    c(&mut gl, Call::CreateContext { id: 7 });
    c(&mut gl, Call::MakeCurrent { id: 7 });
    run(&mut gl, offscreen_state());
    attribute_from(&mut gl, 2);
    let recorded = drawing(&mut gl, |gl, window| {
        c(gl, Call::MakeCurrent { id: if window { 0 } else { 7 } });
    });
    let json = gl.recording().unwrap().to_json();
    assert!(json.contains(r#"{"call":"make_current","id":7}"#), "{json}");
    let trace = trace::Trace::parse(&json, None).unwrap();
    let replay = trace.replay().unwrap();
    let texture = replay.context.device().read_rgba8(replay.context.texture_image(TARGET).unwrap()).unwrap();
    assert!((replay.context.surface_rgba8(), texture) == recorded);
}
