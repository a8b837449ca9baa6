"""A room with a hard shadow, as OBJ + MTL (bench/hard_shadow.sh; the same room as the test
EndToEnd.EstimatedErrorsMatchThePathTracedReferenceOnAHardShadow).

A closed room 4 x 3 x 4 m (walls facing in; one red, one green), a small bright lamp (0.3 x 0.3)
just under the ceiling facing down, and a table top (1.2 x 1.2, two-sided: two faces back to
back) floating at y = 1: a hard shadow on the floor, nothing touching.
Usage: python3 bench/shadow_room.py DIR   (writes DIR/shadow.obj and DIR/shadow.mtl)
"""
import os
import sys

out = sys.argv[1] if len(sys.argv) > 1 else "."
V=[]; F=[]
def quad(p, mat):
    base=len(V)+1
    V.extend(p); F.append((mat, [base, base+1, base+2, base+3]))
W,H,D=4.0,3.0,4.0
# floor (normal +y): counter-clockwise seen from above
quad([(0,0,0),(0,0,D),(W,0,D),(W,0,0)],'white')
quad([(0,H,0),(W,H,0),(W,H,D),(0,H,D)],'white')  # ceiling, normal -y
quad([(0,0,0),(W,0,0),(W,H,0),(0,H,0)],'white')  # back wall z=0, normal +z
quad([(0,0,D),(0,H,D),(W,H,D),(W,0,D)],'white')  # z=D normal -z
quad([(0,0,0),(0,H,0),(0,H,D),(0,0,D)],'red')    # x=0 normal +x
quad([(W,0,0),(W,0,D),(W,H,D),(W,H,0)],'green')  # x=W normal -x
l=0.15; cx,cz=2.0,2.0; y=H-0.01
quad([(cx-l,y,cz-l),(cx+l,y,cz-l),(cx+l,y,cz+l),(cx-l,y,cz+l)],'light')  # normal -y
t=0.6; ty=1.0; tx,tz=1.7,2.2
quad([(tx-t,ty,tz-t),(tx-t,ty,tz+t),(tx+t,ty,tz+t),(tx+t,ty,tz-t)],'table')  # up
quad([(tx-t,ty,tz-t),(tx+t,ty,tz-t),(tx+t,ty,tz+t),(tx-t,ty,tz+t)],'table')  # down
with open(os.path.join(out, 'shadow.mtl'),'w') as m:
    m.write('newmtl white\nKd 0.7 0.7 0.7\nnewmtl red\nKd 0.6 0.1 0.1\nnewmtl green\nKd 0.1 0.6 0.1\n')
    m.write('newmtl light\nKd 0 0 0\nKe 200 180 150\nnewmtl table\nKd 0.5 0.4 0.3\n')
with open(os.path.join(out, 'shadow.obj'),'w') as o:
    o.write('mtllib shadow.mtl\n')
    for v in V: o.write('v %g %g %g\n'%v)
    cur=None
    for mat,f in F:
        if mat!=cur: o.write('usemtl %s\n'%mat); cur=mat
        o.write('f '+' '.join(map(str,f))+'\n')
