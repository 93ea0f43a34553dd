// A struct for test/Tools/shader-group-connections.osl.
struct Pair {
    float s;
    color c;
};
