// For line_macro_main_and_header.osl: __LINE__ on line 3 of this header.
int header_line() {
    return __LINE__;
}
