// An error inside an included file is reported at its own position.
float broken(float x) { return x +; }
