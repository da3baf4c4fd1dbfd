# SPDX-License-Identifier: MIT
# example-inputs.sh -- sourced by check-examples.sh and check-mpi.sh:
# example_inputs DIR writes the tiny inputs both give the examples that
# read a file: DIR/tri.obj (three triangles) and DIR/patch.bpt (one
# bicubic Bezier patch in Newell's format).
example_inputs() {
    cat > "$1/tri.obj" <<'OBJ'
v -1 0 0
v 1 0 0
v 0 1.5 0.3
v 0 0.5 -1
f 1 2 3
f 1 3 4
f 2 4 3
OBJ
    {
        echo 1
        echo 1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16
        echo 16
        for y in 0 1 2 3; do
            for x in 0 1 2 3; do echo "$x, $y, 0.$((x * y))"; done
        done
    } > "$1/patch.bpt"
}
