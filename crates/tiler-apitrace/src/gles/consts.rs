//! GL enum values this crate itself uses or that tests and consumers commonly compare against
//! (values from the Khronos `gl2.h`/`gl3.h` headers).

use super::GlEnum;

pub const GL_POINTS: GlEnum = 0x0000;
pub const GL_LINES: GlEnum = 0x0001;
pub const GL_TRIANGLES: GlEnum = 0x0004;
pub const GL_TRIANGLE_STRIP: GlEnum = 0x0005;
pub const GL_TRIANGLE_FAN: GlEnum = 0x0006;
pub const GL_FRONT: GlEnum = 0x0404;
pub const GL_BACK: GlEnum = 0x0405;
pub const GL_FRONT_AND_BACK: GlEnum = 0x0408;
pub const GL_CULL_FACE: GlEnum = 0x0b44;
pub const GL_DEPTH_TEST: GlEnum = 0x0b71;
pub const GL_STENCIL_TEST: GlEnum = 0x0b90;
pub const GL_BLEND: GlEnum = 0x0be2;
pub const GL_SCISSOR_TEST: GlEnum = 0x0c11;
pub const GL_TEXTURE_2D: GlEnum = 0x0de1;
pub const GL_UNSIGNED_BYTE: GlEnum = 0x1401;
pub const GL_UNSIGNED_SHORT: GlEnum = 0x1403;
pub const GL_UNSIGNED_INT: GlEnum = 0x1405;
pub const GL_FLOAT: GlEnum = 0x1406;
pub const GL_DEPTH_COMPONENT: GlEnum = 0x1902;
pub const GL_RGB: GlEnum = 0x1907;
pub const GL_RGBA: GlEnum = 0x1908;
pub const GL_TEXTURE0: GlEnum = 0x84c0;
pub const GL_ARRAY_BUFFER: GlEnum = 0x8892;
pub const GL_ELEMENT_ARRAY_BUFFER: GlEnum = 0x8893;
pub const GL_UNIFORM_BUFFER: GlEnum = 0x8a11;
pub const GL_WRITE_ONLY_OES: GlEnum = 0x88b9;
pub const GL_FRAGMENT_SHADER: GlEnum = 0x8b30;
pub const GL_VERTEX_SHADER: GlEnum = 0x8b31;
pub const GL_FRAMEBUFFER: GlEnum = 0x8d40;
pub const GL_RENDERBUFFER: GlEnum = 0x8d41;
pub const GL_COLOR_ATTACHMENT0: GlEnum = 0x8ce0;
pub const GL_DEPTH_ATTACHMENT: GlEnum = 0x8d00;
pub const GL_STENCIL_ATTACHMENT: GlEnum = 0x8d20;
pub const GL_DEPTH_BUFFER_BIT: u32 = 0x0100;
pub const GL_STENCIL_BUFFER_BIT: u32 = 0x0400;
pub const GL_COLOR_BUFFER_BIT: u32 = 0x4000;
