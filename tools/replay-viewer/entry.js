// The parts of three.js the replay viewer uses (templates/assets/replay/replay.js), bundled by
// refresh.sh into one classic script that defines window.SITEGEN_THREE: a page opened from
// file:// cannot import ES modules (Chromium treats file:// as an opaque origin), but it can
// run a plain <script src>.
export {
  AnimationMixer,
  Color,
  DirectionalLight,
  HemisphereLight,
  LoopOnce,
  MeshLambertMaterial,
  PerspectiveCamera,
  PropertyBinding,
  Quaternion,
  REVISION,
  Scene,
  Vector3,
  WebGLRenderer,
} from "three";
export { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
export { OrbitControls } from "three/addons/controls/OrbitControls.js";
