// The three.js stage: renderer, a studio's lights (key high left, fill low right, rim
// behind, as the path tracer's `studio` preset places them) over the page's light backdrop,
// the orbit camera, and drawing on demand: nothing is drawn unless something changed.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';

export class Stage {
  constructor(canvas, onChange) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, alpha: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.setClearColor(0x000000, 0);  // the backdrop is the page's (player.css #stage)
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', onChange);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0xb9b6ae, 1.1));
    this.lights = [[-1.2, 1.6, 1.6, 2.2], [1.4, 0.2, 1.2, 0.8], [0.3, 1.2, -2.0, 1.0]].map(([x, y, z, power]) => {
      const light = new THREE.DirectionalLight(0xffffff, power);
      light.position.set(x, y, z);
      this.scene.add(light);
      return light;
    });
    this.home = null;  // where reset() puts the camera
    this.renders = 0;
    new ResizeObserver(() => { this.resize(); onChange(); }).observe(canvas);
    this.resize();
  }

  resize() {
    const w = Math.max(1, this.canvas.clientWidth), h = Math.max(1, this.canvas.clientHeight);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  // Frames `geometry` (its bounding sphere) and remembers the view for reset().
  frame(geometry) {
    geometry.computeBoundingSphere();
    const { center, radius } = geometry.boundingSphere;
    const fov = THREE.MathUtils.degToRad(this.camera.fov / 2);
    const fit = Math.min(fov, Math.atan(Math.tan(fov) * this.camera.aspect));
    const distance = (radius / Math.sin(fit)) * 1.08;
    this.home = { position: new THREE.Vector3(center.x, center.y, center.z + distance), target: center.clone(), distance };
    this.reset();
  }

  reset() {
    if (!this.home) return;
    this.camera.position.copy(this.home.position);
    this.camera.near = this.home.distance / 100;
    this.camera.far = this.home.distance * 10;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(this.home.target);
    this.controls.update();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
    this.renders++;
  }
}
