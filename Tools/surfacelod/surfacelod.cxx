// Placeholder: the command-line tool is being written.
#include <cstdio>
int main() { std::puts("surfacelod"); return 0; }
