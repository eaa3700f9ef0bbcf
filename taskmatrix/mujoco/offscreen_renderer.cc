#include "taskmatrix/mujoco/offscreen_renderer.h"

#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>


namespace taskmatrix::mujoco {

struct OffscreenRenderer::Impl {
  OSMesaContext context = nullptr;
  std::vector<unsigned char> framebuffer;  // OSMesa's colour buffer (RGBA)
  mjvScene scene;
  mjvOption option;
  mjrContext render_context;
  std::vector<unsigned char> rgb;
  std::vector<float> depth;
};

OffscreenRenderer::OffscreenRenderer(const mjModel* model, int width, int height)
    : impl_(std::make_unique<Impl>()), width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > model->vis.global.offwidth ||
      height > model->vis.global.offheight) {
    throw std::runtime_error("render size " + std::to_string(width) + "x" + std::to_string(height) +
                             " must be positive and within the model's offscreen buffer " +
                             std::to_string(model->vis.global.offwidth) + "x" +
                             std::to_string(model->vis.global.offheight));
  }
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            24,
                            OSMESA_STENCIL_BITS,
                            8,
                            OSMESA_PROFILE,
                            OSMESA_COMPAT_PROFILE,
                            0};
  impl_->context = OSMesaCreateContextAttribs(attributes, nullptr);
  if (!impl_->context) throw std::runtime_error("OSMesa cannot create a rendering context");
  impl_->framebuffer.resize(static_cast<size_t>(model->vis.global.offwidth) *
                            model->vis.global.offheight * 4);
  if (!OSMesaMakeCurrent(impl_->context, impl_->framebuffer.data(), GL_UNSIGNED_BYTE,
                         model->vis.global.offwidth, model->vis.global.offheight)) {
    OSMesaDestroyContext(impl_->context);
    throw std::runtime_error("OSMesa cannot make its context current");
  }
  mjv_defaultScene(&impl_->scene);
  mjv_defaultOption(&impl_->option);
  mjr_defaultContext(&impl_->render_context);
  mjv_makeScene(model, &impl_->scene, 4000);
  mjr_makeContext(model, &impl_->render_context, mjFONTSCALE_100);
  mjr_setBuffer(mjFB_OFFSCREEN, &impl_->render_context);
  impl_->rgb.resize(static_cast<size_t>(width) * height * 3);
  impl_->depth.resize(static_cast<size_t>(width) * height);
}

OffscreenRenderer::~OffscreenRenderer() {
  OSMesaMakeCurrent(impl_->context, impl_->framebuffer.data(), GL_UNSIGNED_BYTE, 1, 1);
  mjr_freeContext(&impl_->render_context);
  mjv_freeScene(&impl_->scene);
  OSMesaDestroyContext(impl_->context);
}

void OffscreenRenderer::draw(const mjModel* model, mjData* data, const CameraView& view) {
  // Several renderers may share a thread: make ours current every time.
  OSMesaMakeCurrent(impl_->context, impl_->framebuffer.data(), GL_UNSIGNED_BYTE,
                    model->vis.global.offwidth, model->vis.global.offheight);
  mjvCamera camera;
  mjv_defaultCamera(&camera);
  if (view.fixed_camera >= 0) {
    if (view.fixed_camera >= model->ncam) throw std::runtime_error("camera id out of range");
    camera.type = mjCAMERA_FIXED;
    camera.fixedcamid = view.fixed_camera;
  } else {
    camera.type = mjCAMERA_FREE;
    std::copy(view.lookat, view.lookat + 3, camera.lookat);
    camera.distance = view.distance;
    camera.azimuth = view.azimuth;
    camera.elevation = view.elevation;
  }
  mjv_updateScene(model, data, &impl_->option, nullptr, &camera, mjCAT_ALL, &impl_->scene);
  const mjrRect viewport{0, 0, width_, height_};
  mjr_render(viewport, &impl_->scene, &impl_->render_context);
  mjr_readPixels(impl_->rgb.data(), impl_->depth.data(), viewport, &impl_->render_context);
}

RgbImage OffscreenRenderer::render_rgb(const mjModel* model, mjData* data, const CameraView& view) {
  draw(model, data, view);
  RgbImage image{width_, height_, std::vector<std::uint8_t>(impl_->rgb.size())};
  const size_t row = static_cast<size_t>(width_) * 3;
  for (int y = 0; y < height_; ++y) {  // OpenGL's rows run bottom-up
    std::copy_n(impl_->rgb.begin() + (height_ - 1 - y) * row, row, image.pixels.begin() + y * row);
  }
  return image;
}

DepthImage OffscreenRenderer::render_depth(const mjModel* model, mjData* data,
                                           const CameraView& view) {
  draw(model, data, view);
  const double extent = model->stat.extent;
  const double znear = model->vis.map.znear * extent;
  const double zfar = model->vis.map.zfar * extent;
  DepthImage image{width_, height_, std::vector<float>(impl_->depth.size())};
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const double d = impl_->depth[static_cast<size_t>(height_ - 1 - y) * width_ + x];
      image.metres[static_cast<size_t>(y) * width_ + x] =
          d >= 1.0 ? std::numeric_limits<float>::infinity()
                   : static_cast<float>(znear / (1.0 - d * (1.0 - znear / zfar)));
    }
  }
  return image;
}

}  // namespace taskmatrix::mujoco
