// Arguments: N, then N pairs VARIABLE VALUE (as Player prints them), then the
// events' indices. Without events it prints the initial state line.
int main(int argc, char** argv) {

