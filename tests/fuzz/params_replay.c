/* Runs the fuzz target on each file named on the command line: the committed
 * corpus replayed by ctest with any compiler (the fuzzer itself needs clang). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv)
{
    for (int k = 1; k < argc; ++k) {
        FILE *f = fopen(argv[k], "rb");
        uint8_t *buf;
        long len;
        if (!f || fseek(f, 0, SEEK_END) != 0 || (len = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
            fprintf(stderr, "params_replay: %s: cannot read\n", argv[k]);
            return 1;
        }
        buf = malloc((size_t)len + 1);
        if (!buf || fread(buf, 1, (size_t)len, f) != (size_t)len) {
            fprintf(stderr, "params_replay: %s: cannot read\n", argv[k]);
            return 1;
        }
        fclose(f);
        LLVMFuzzerTestOneInput(buf, (size_t)len);
        free(buf);
    }
    printf("params_replay: %d inputs\n", argc - 1);
    return 0;
}
