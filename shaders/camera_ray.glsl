// Camera rays: the same construction as Camera::rayThroughPixel. Included by shade.frag and sky.frag after
// their camera uniforms (TD_LOC_CAMERA_POS .. TD_LOC_FRAME_SIZE, ShadePass's cameraVectors); not standalone.
void cameraRay(vec2 fragXY, out vec3 origin, out vec3 dir) {
  // gl_FragCoord has y up; the camera's pixel y runs down, and 1 - 2·(H - y)/H = 2·y/H - 1.
  float nx = fragXY.x / float(frameSize.x) * 2.0 - 1.0;
  float ny = fragXY.y / float(frameSize.y) * 2.0 - 1.0;
  if (orthographic != 0) {
    origin = cameraPosW + cameraRight * nx + cameraUp * ny;
    dir = cameraForward;
  } else {
    origin = cameraPosW;
    dir = normalize(cameraForward + cameraRight * nx + cameraUp * ny);
  }
}
