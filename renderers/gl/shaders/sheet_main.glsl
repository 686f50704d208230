
void main() { emit(); }
