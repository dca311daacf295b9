// renderer.cpp — OSMesa context, fixed-function GL drawing of boxes, spheres, capsules, the checkered
// ground and the HUD line. Unit meshes are built once per Renderer; capsules reuse the unit-sphere
// rings with the two hemispheres pushed apart by halfLength.
#include "engine/render/renderer.h"

#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "engine/core/error.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include "stb_easy_font.h"
#pragma GCC diagnostic pop

namespace engine {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kZNear = 0.05;                 // [m]
constexpr double kZFar = 300.0;                 // [m]
constexpr double kDefaultPlaneHalfSize = 50.0;  // [m]
constexpr int kSlices = 16;                     // round meshes: vertices around the Z axis
constexpr int kHemisphereSteps = 6;             // round meshes: latitude steps per hemisphere
constexpr int kPlaneTiles = 20;                 // ground grid tiles per side (fog is per vertex)
constexpr int kCheckerTexels = 64;              // checker texture size; holds 2 x 2 one-metre squares
constexpr int kHudScale = 2;                    // HUD font magnification
constexpr int kHudPadding = 4;                  // HUD strip padding [px, before scaling]
constexpr GLfloat kSky[4] = {0.53f, 0.74f, 0.92f, 1.0f};

// an indexed triangle mesh with per-vertex normals
struct Mesh {
  std::vector<GLfloat> positions;  // xyz per vertex
  std::vector<GLfloat> normals;    // xyz per vertex
  std::vector<GLushort> indices;   // 3 per triangle, counter-clockwise seen from outside
};

// the unit cube [-1, 1]^3 with flat faces
Mesh makeUnitBox() {
  // each face: outward normal n and tangents u, v with u x v = n, so the corner order below is CCW
  static const int faces[6][3][3] = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
      {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
  };
  static const int corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  Mesh mesh;
  for (const auto& face : faces) {
    const auto base = static_cast<GLushort>(mesh.positions.size() / 3);
    for (const auto& c : corners) {
      for (int k = 0; k < 3; ++k) {
        mesh.positions.push_back(static_cast<GLfloat>(face[0][k] + c[0] * face[1][k] + c[1] * face[2][k]));
        mesh.normals.push_back(static_cast<GLfloat>(face[0][k]));
      }
    }
    for (int i : {0, 1, 2, 0, 2, 3}) mesh.indices.push_back(static_cast<GLushort>(base + i));
  }
  return mesh;
}

// the unit sphere as rings from the south to the north pole; the equator ring appears twice so a
// capsule can move the southern rings down and the northern rings up (sides[i] = -1 or +1)
struct RoundMesh {
  Mesh sphere;
  std::vector<GLfloat> sides;  // per vertex: -1 southern hemisphere, +1 northern
};

RoundMesh makeUnitRound() {
  RoundMesh round;
  const int rings = 2 * (kHemisphereSteps + 1);
  for (int ring = 0; ring < rings; ++ring) {
    const bool north = ring > kHemisphereSteps;
    const int step = north ? ring - (kHemisphereSteps + 1) : ring;  // 0..kHemisphereSteps
    const double lat = (north ? 0.0 : -0.5 * kPi) + 0.5 * kPi * step / kHemisphereSteps;
    for (int j = 0; j < kSlices; ++j) {
      const double lon = 2.0 * kPi * j / kSlices;
      const GLfloat n[3] = {static_cast<GLfloat>(std::cos(lat) * std::cos(lon)),
                            static_cast<GLfloat>(std::cos(lat) * std::sin(lon)), static_cast<GLfloat>(std::sin(lat))};
      round.sphere.positions.insert(round.sphere.positions.end(), n, n + 3);
      round.sphere.normals.insert(round.sphere.normals.end(), n, n + 3);
      round.sides.push_back(north ? 1.0f : -1.0f);
    }
  }
  for (int ring = 0; ring + 1 < rings; ++ring) {
    for (int j = 0; j < kSlices; ++j) {
      // a, b on the lower ring, c, d above them; longitude grows counter-clockwise seen from +Z
      const auto a = static_cast<GLushort>(ring * kSlices + j);
      const auto b = static_cast<GLushort>(ring * kSlices + (j + 1) % kSlices);
      const auto c = static_cast<GLushort>(a + kSlices);
      const auto d = static_cast<GLushort>(b + kSlices);
      for (GLushort i : {a, b, d, a, d, c}) round.sphere.indices.push_back(i);
    }
  }
  return round;
}

void drawMesh(const GLfloat* positions, const Mesh& mesh) {
  glVertexPointer(3, GL_FLOAT, 0, positions);
  glNormalPointer(GL_FLOAT, 0, mesh.normals.data());
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(mesh.indices.size()), GL_UNSIGNED_SHORT, mesh.indices.data());
}

void setColour(uint32_t rgba) {
  glColor4ub(static_cast<GLubyte>(rgba >> 24), static_cast<GLubyte>(rgba >> 16), static_cast<GLubyte>(rgba >> 8),
             static_cast<GLubyte>(rgba));
}

bool isTransparent(const DrawShape& shape) { return (shape.rgba & 0xffu) < 0xffu; }

// a Plane's drawn half size along x (axis 0) or y (axis 1) [m]; 0 means the default
double planeHalfSize(const DrawShape& plane, int axis) {
  const double h = plane.halfExtents[axis];
  return h > 0.0 ? h : kDefaultPlaneHalfSize;
}

}  // namespace

struct Renderer::Gl {
  OSMesaContext context = nullptr;
  std::vector<uint8_t> buffer;  // OSMesa colour buffer, rows bottom-up
  GLuint checkerTexture = 0;
  Mesh box = makeUnitBox();
  RoundMesh round = makeUnitRound();
  std::vector<GLfloat> capsulePositions;  // scratch, rebuilt per capsule
  std::vector<char> hudVertices;          // scratch for stb_easy_font quads

  void makeCurrent(int width, int height) {
    if (!OSMesaMakeCurrent(context, buffer.data(), GL_UNSIGNED_BYTE, width, height))
      throw Error("renderer: OSMesaMakeCurrent failed");
  }

  // a 2 x 2 checker of one-metre squares in two greys, with box-filtered mipmaps so far squares fade to grey
  void createCheckerTexture() {
    std::vector<GLubyte> level(kCheckerTexels * kCheckerTexels);
    const int half = kCheckerTexels / 2;
    for (int y = 0; y < kCheckerTexels; ++y)
      for (int x = 0; x < kCheckerTexels; ++x) level[y * kCheckerTexels + x] = ((x < half) == (y < half)) ? 205 : 255;

    glGenTextures(1, &checkerTexture);
    glBindTexture(GL_TEXTURE_2D, checkerTexture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (int size = kCheckerTexels, mip = 0; size >= 1; size /= 2, ++mip) {
      glTexImage2D(GL_TEXTURE_2D, mip, GL_LUMINANCE, size, size, 0, GL_LUMINANCE, GL_UNSIGNED_BYTE, level.data());
      if (size == 1) break;
      // average 2 x 2 blocks into the next level
      const int next = size / 2;
      std::vector<GLubyte> smaller(next * next);
      for (int y = 0; y < next; ++y)
        for (int x = 0; x < next; ++x) {
          const int sum = level[(2 * y) * size + 2 * x] + level[(2 * y) * size + 2 * x + 1] +
                          level[(2 * y + 1) * size + 2 * x] + level[(2 * y + 1) * size + 2 * x + 1];
          smaller[y * next + x] = static_cast<GLubyte>((sum + 2) / 4);
        }
      level.swap(smaller);
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glBindTexture(GL_TEXTURE_2D, 0);
  }

  // one shape, in world coordinates; the modelview holds the view matrix on entry and exit
  void drawShape(const DrawShape& shape, const Eigen::Vector3d& follow) {
    setColour(shape.rgba);
    if (shape.kind == ShapeKind::Plane) {
      drawPlane(shape, follow);
      return;
    }
    Eigen::Matrix4d model = Eigen::Matrix4d::Identity();
    model.topLeftCorner<3, 3>() = shape.rotation.normalized().toRotationMatrix();
    model.topRightCorner<3, 1>() = shape.position;
    glPushMatrix();
    glMultMatrixd(model.data());
    switch (shape.kind) {
      case ShapeKind::Box:
        if (shape.halfExtents.minCoeff() > 0.0) {
          glScaled(shape.halfExtents.x(), shape.halfExtents.y(), shape.halfExtents.z());
          drawMesh(box.positions.data(), box);
        }
        break;
      case ShapeKind::Sphere:
        if (shape.radius > 0.0) {
          glScaled(shape.radius, shape.radius, shape.radius);
          drawMesh(round.sphere.positions.data(), round.sphere);
        }
        break;
      case ShapeKind::Capsule:
        if (shape.radius > 0.0) drawCapsule(shape.radius, std::max(0.0, shape.halfLength));
        break;
      case ShapeKind::Plane:
        break;
    }
    glPopMatrix();
  }

  void drawCapsule(double radius, double halfLength) {
    // unit-sphere rings scaled by radius, hemispheres shifted to +-halfLength along local Z
    const std::vector<GLfloat>& unit = round.sphere.positions;
    capsulePositions.resize(unit.size());
    const auto r = static_cast<GLfloat>(radius);
    const auto h = static_cast<GLfloat>(halfLength);
    for (size_t v = 0; v < round.sides.size(); ++v) {
      capsulePositions[3 * v + 0] = r * unit[3 * v + 0];
      capsulePositions[3 * v + 1] = r * unit[3 * v + 1];
      capsulePositions[3 * v + 2] = r * unit[3 * v + 2] + round.sides[v] * h;
    }
    drawMesh(capsulePositions.data(), round.sphere);
  }

  // a horizontal checkered square around the follow point (snapped to whole squares) at the plane's z,
  // split into a grid of tiles because fixed-function fog is evaluated per vertex
  void drawPlane(const DrawShape& shape, const Eigen::Vector3d& follow) {
    const double hx = planeHalfSize(shape, 0);
    const double hy = planeHalfSize(shape, 1);
    const double x0 = std::round(follow.x()) - hx;
    const double y0 = std::round(follow.y()) - hy;
    const double z = shape.position.z();
    const double stepX = 2.0 * hx / kPlaneTiles;
    const double stepY = 2.0 * hy / kPlaneTiles;
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, checkerTexture);
    glBegin(GL_QUADS);
    glNormal3d(0.0, 0.0, 1.0);
    for (int i = 0; i < kPlaneTiles; ++i) {
      for (int j = 0; j < kPlaneTiles; ++j) {
        // counter-clockwise seen from above; the texture repeats every 2 m (2 x 2 squares)
        const double corners[4][2] = {{x0 + i * stepX, y0 + j * stepY},
                                      {x0 + (i + 1) * stepX, y0 + j * stepY},
                                      {x0 + (i + 1) * stepX, y0 + (j + 1) * stepY},
                                      {x0 + i * stepX, y0 + (j + 1) * stepY}};
        for (const auto& c : corners) {
          glTexCoord2d(0.5 * c[0], 0.5 * c[1]);
          glVertex3d(c[0], c[1], z);
        }
      }
    }
    glEnd();
    glBindTexture(GL_TEXTURE_2D, 0);
    glDisable(GL_TEXTURE_2D);
  }

  // white text on a translucent dark strip, top-left, in pixel coordinates (y down)
  void drawHud(const std::string& text, int width, int height) {
    // stb_easy_font indexes a table by (char - 32): keep printable ASCII and newlines only
    std::string clean = text;
    for (char& ch : clean)
      if (ch != '\n' && (ch < 32 || ch > 126)) ch = '?';
    hudVertices.resize(clean.size() * 300 + 64);
    const int quads = stb_easy_font_print(0.0f, 0.0f, clean.data(), nullptr, hudVertices.data(),
                                          static_cast<int>(hudVertices.size()));
    const int stripW = (stb_easy_font_width(clean.data()) + 2 * kHudPadding) * kHudScale;
    const int stripH = (stb_easy_font_height(clean.data()) + 2 * kHudPadding) * kHudScale;

    glDisable(GL_LIGHTING);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_FOG);
    glDisable(GL_CULL_FACE);
    glDisableClientState(GL_NORMAL_ARRAY);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0.0, width, height, 0.0, -1.0, 1.0);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();

    glColor4ub(0, 0, 0, 140);
    glRecti(0, 0, stripW, stripH);

    glTranslatef(static_cast<GLfloat>(kHudPadding * kHudScale), static_cast<GLfloat>(kHudPadding * kHudScale), 0.0f);
    glScalef(static_cast<GLfloat>(kHudScale), static_cast<GLfloat>(kHudScale), 1.0f);
    glColor4ub(255, 255, 255, 255);
    glVertexPointer(2, GL_FLOAT, 16, hudVertices.data());
    glDrawArrays(GL_QUADS, 0, quads * 4);

    glEnableClientState(GL_NORMAL_ARRAY);
    glDisable(GL_BLEND);
  }
};

Renderer::Renderer(int width, int height) : width_(width), height_(height), gl_(std::make_unique<Gl>()) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw Error("renderer: invalid image size " + std::to_string(width) + "x" + std::to_string(height));
  gl_->context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!gl_->context) throw Error("renderer: cannot create an OSMesa context (RGBA, 24-bit depth)");
  gl_->buffer.assign(static_cast<size_t>(width) * height * 4, 0);
  image_.assign(gl_->buffer.size(), 0);
  camera_.width = width;
  camera_.height = height;
  try {
    gl_->makeCurrent(width, height);
    gl_->createCheckerTexture();
  } catch (...) {
    OSMesaDestroyContext(gl_->context);
    throw;
  }
}

Renderer::~Renderer() {
  if (gl_ && gl_->context) OSMesaDestroyContext(gl_->context);
}

void Renderer::render(const SceneSnapshot& snapshot) {
  gl_->makeCurrent(width_, height_);
  camera_ = followCamera(snapshot, width_, height_);

  // per-frame state: depth test, Gouraud lighting with one directional light, colour material, fog
  glViewport(0, 0, width_, height_);
  glClearColor(kSky[0], kSky[1], kSky[2], kSky[3]);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glShadeModel(GL_SMOOTH);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glEnable(GL_NORMALIZE);
  glEnable(GL_LIGHTING);
  glEnable(GL_LIGHT0);
  glEnable(GL_COLOR_MATERIAL);
  glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  const GLfloat noAmbient[4] = {0.0f, 0.0f, 0.0f, 1.0f};
  const GLfloat ambient[4] = {0.38f, 0.38f, 0.40f, 1.0f};
  const GLfloat diffuse[4] = {0.70f, 0.70f, 0.66f, 1.0f};
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, noAmbient);
  glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
  glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
  glLightfv(GL_LIGHT0, GL_SPECULAR, noAmbient);
  glDisable(GL_BLEND);

  glMatrixMode(GL_PROJECTION);
  const Eigen::Matrix4d projection = projectionMatrix(camera_, kZNear, kZFar);
  glLoadMatrixd(projection.data());
  glMatrixMode(GL_MODELVIEW);
  const Eigen::Matrix4d view = viewMatrix(camera_);
  glLoadMatrixd(view.data());
  // light travels from the upper left and slightly from the camera side (w = 0: a direction, in world frame)
  const GLfloat toLight[4] = {-0.35f, -0.55f, 0.76f, 0.0f};
  glLightfv(GL_LIGHT0, GL_POSITION, toLight);

  // distance fog hides the edge of the finite ground square
  double planeHalf = 0.0;
  for (const DrawShape& shape : snapshot.shapes)
    if (shape.kind == ShapeKind::Plane)
      planeHalf = std::max(planeHalf, std::min(planeHalfSize(shape, 0), planeHalfSize(shape, 1)));
  if (planeHalf > 0.0) {
    glEnable(GL_FOG);
    glFogi(GL_FOG_MODE, GL_LINEAR);
    glFogfv(GL_FOG_COLOR, kSky);
    glFogf(GL_FOG_START, static_cast<GLfloat>(0.55 * planeHalf));
    glFogf(GL_FOG_END, static_cast<GLfloat>(planeHalf));
  } else {
    glDisable(GL_FOG);
  }

  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_NORMAL_ARRAY);

  // opaque shapes first, then see-through ones far to near with blending and no depth writes
  std::vector<const DrawShape*> transparent;
  for (const DrawShape& shape : snapshot.shapes) {
    if (isTransparent(shape))
      transparent.push_back(&shape);
    else
      gl_->drawShape(shape, snapshot.follow);
  }
  if (!transparent.empty()) {
    const Eigen::Vector3d eye = camera_.eye;
    std::sort(transparent.begin(), transparent.end(), [&eye](const DrawShape* a, const DrawShape* b) {
      return (a->position - eye).squaredNorm() > (b->position - eye).squaredNorm();
    });
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    for (const DrawShape* shape : transparent) gl_->drawShape(*shape, snapshot.follow);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }

  if (!snapshot.hud.empty()) gl_->drawHud(snapshot.hud, width_, height_);

  glDisableClientState(GL_VERTEX_ARRAY);
  glDisableClientState(GL_NORMAL_ARRAY);
  glFinish();

  // OSMesa rows are bottom-up; the public image is top-down
  const size_t rowBytes = static_cast<size_t>(width_) * 4;
  for (int y = 0; y < height_; ++y)
    std::memcpy(image_.data() + static_cast<size_t>(y) * rowBytes,
                gl_->buffer.data() + static_cast<size_t>(height_ - 1 - y) * rowBytes, rowBytes);
}

}  // namespace engine
