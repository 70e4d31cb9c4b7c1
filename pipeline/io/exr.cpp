#include "pipeline/io/exr.h"

#include "pipeline/io/files.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfStringVectorAttribute.h>

#include <stdexcept>
#include <vector>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

struct Planes {
  std::vector<half> r, g, b, a, nx, ny, nz, ar, ag, ab;
  std::vector<float> depth;
  std::vector<uint32_t> id;
};

template <class T>
void slice(Imf::FrameBuffer& fb, const char* name, Imf::PixelType type, std::vector<T>& plane, int width) {
  fb.insert(name, Imf::Slice(type, reinterpret_cast<char*>(plane.data()), sizeof(T), sizeof(T) * size_t(width)));
}

}  // namespace

void writeExr(const fs::path& path, const render::Image& beauty, const render::FrameLayers* layers, double time,
              int frame, const FileStamp* stamp) {
  const int w = beauty.width(), h = beauty.height();
  if (layers && (layers->width != w || layers->height != h))
    throw std::invalid_argument(path.string() + ": layers of another size than the frame");
  const size_t n = size_t(w) * size_t(h);
  Planes p;
  for (auto* v : {&p.r, &p.g, &p.b, &p.a}) v->resize(n);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const Eigen::Vector4f& c = beauty.at(x, y);
      p.r[i] = half(c.x());
      p.g[i] = half(c.y());
      p.b[i] = half(c.z());
      p.a[i] = half(c.w());
    }
  Imf::Header header(w, h);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.insert("kurage:time", Imf::DoubleAttribute(time));
  header.insert("kurage:frame", Imf::IntAttribute(frame));
  if (stamp) header.insert("kurage:stamp", Imf::StringAttribute(stampText(*stamp)));
  Imf::FrameBuffer fb;
  for (const char* c : {"R", "G", "B", "A"}) header.channels().insert(c, Imf::Channel(Imf::HALF));
  slice(fb, "R", Imf::HALF, p.r, w);
  slice(fb, "G", Imf::HALF, p.g, w);
  slice(fb, "B", Imf::HALF, p.b, w);
  slice(fb, "A", Imf::HALF, p.a, w);
  if (layers) {
    p.depth = layers->depth;
    p.id = layers->objectId;
    for (auto* v : {&p.nx, &p.ny, &p.nz, &p.ar, &p.ag, &p.ab}) v->resize(n);
    for (size_t i = 0; i < n; ++i) {
      p.nx[i] = half(layers->normal[i].x());
      p.ny[i] = half(layers->normal[i].y());
      p.nz[i] = half(layers->normal[i].z());
      p.ar[i] = half(layers->albedo[i].x());
      p.ag[i] = half(layers->albedo[i].y());
      p.ab[i] = half(layers->albedo[i].z());
    }
    header.channels().insert("depth.Z", Imf::Channel(Imf::FLOAT));
    header.channels().insert("object_id", Imf::Channel(Imf::UINT));
    for (const char* c : {"normal.X", "normal.Y", "normal.Z", "albedo.R", "albedo.G", "albedo.B"})
      header.channels().insert(c, Imf::Channel(Imf::HALF));
    if (!layers->objectNames.empty())
      header.insert("kurage:object_names", Imf::StringVectorAttribute(layers->objectNames));
    slice(fb, "depth.Z", Imf::FLOAT, p.depth, w);
    slice(fb, "object_id", Imf::UINT, p.id, w);
    slice(fb, "normal.X", Imf::HALF, p.nx, w);
    slice(fb, "normal.Y", Imf::HALF, p.ny, w);
    slice(fb, "normal.Z", Imf::HALF, p.nz, w);
    slice(fb, "albedo.R", Imf::HALF, p.ar, w);
    slice(fb, "albedo.G", Imf::HALF, p.ag, w);
    slice(fb, "albedo.B", Imf::HALF, p.ab, w);
  }
  // OpenEXR writes the temporary by its name; TempFile removes it on failure and commits it
  // (fsync, rename, folder fsync) on success.
  TempFile tmp(path);
  try {
    Imf::OutputFile file(tmp.path().c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(h);
  } catch (const std::exception& e) {
    throw IoError(path.string() + ": cannot write OpenEXR: " + e.what());
  }
  tmp.commit();
}

ExrFrame readExr(const fs::path& path) {
  requireRegularFile(path);
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int w = window.max.x - window.min.x + 1, h = window.max.y - window.min.y + 1;
    const size_t n = size_t(w) * size_t(h);
    ExrFrame out;
    if (const auto* t = file.header().findTypedAttribute<Imf::DoubleAttribute>("kurage:time")) out.time = t->value();
    if (const auto* f = file.header().findTypedAttribute<Imf::IntAttribute>("kurage:frame")) out.frame = f->value();
    if (const auto* st = file.header().findTypedAttribute<Imf::StringAttribute>("kurage:stamp")) out.stamp = st->value();
    out.hasLayers = file.header().channels().findChannel("depth.Z") != nullptr;
    std::vector<float> r(n), g(n), b(n), a(n, 1.0f), depth(n), nx(n), ny(n), nz(n), ar(n), ag(n), ab(n);
    std::vector<uint32_t> id(n);
    Imf::FrameBuffer fb;
    slice(fb, "R", Imf::FLOAT, r, w);
    slice(fb, "G", Imf::FLOAT, g, w);
    slice(fb, "B", Imf::FLOAT, b, w);
    slice(fb, "A", Imf::FLOAT, a, w);
    if (out.hasLayers) {
      slice(fb, "depth.Z", Imf::FLOAT, depth, w);
      slice(fb, "object_id", Imf::UINT, id, w);
      slice(fb, "normal.X", Imf::FLOAT, nx, w);
      slice(fb, "normal.Y", Imf::FLOAT, ny, w);
      slice(fb, "normal.Z", Imf::FLOAT, nz, w);
      slice(fb, "albedo.R", Imf::FLOAT, ar, w);
      slice(fb, "albedo.G", Imf::FLOAT, ag, w);
      slice(fb, "albedo.B", Imf::FLOAT, ab, w);
    }
    file.setFrameBuffer(fb);
    file.readPixels(window.min.y, window.max.y);
    out.beauty = render::Image(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        out.beauty.at(x, y) = Eigen::Vector4f(r[i], g[i], b[i], a[i]);
      }
    if (out.hasLayers) {
      out.layers = render::FrameLayers(w, h);
      out.layers.depth = depth;
      out.layers.objectId = id;
      if (const auto* names = file.header().findTypedAttribute<Imf::StringVectorAttribute>("kurage:object_names"))
        out.layers.objectNames = names->value();
      for (size_t i = 0; i < n; ++i) {
        out.layers.normal[i] = Eigen::Vector3f(nx[i], ny[i], nz[i]);
        out.layers.albedo[i] = Eigen::Vector3f(ar[i], ag[i], ab[i]);
      }
    }
    return out;
  } catch (const std::exception& e) {
    throw std::runtime_error(path.string() + ": cannot read OpenEXR: " + e.what());
  }
}

bool exrStampMatches(const fs::path& path, const FileStamp& expected) {
  if (!fs::exists(path)) return false;
  try {
    return readExr(path).stamp == stampText(expected);
  } catch (const std::exception&) {
    return false;  // damaged or not an EXR: redo it
  }
}

}  // namespace kurage::pipeline
