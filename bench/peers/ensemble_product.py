"""Twin-critic products two ways, forward and backward, in PyTorch: one baddbmm per layer over
weights stacked [2, in, out] (how manyworlds' EnsembleMlp runs twin critics) against two separate
addmm chains (how the PEARL and SAC peers run them).

    python3 bench/peers/ensemble_product.py ROWS HIDDEN    # e.g. 4096 300 (PEARL at oyster's sizes)

Prints the median of 5 timings of 30 passes each way, three rounds.
"""
import time, torch
torch.set_num_threads(1)
import sys
B, H, I = int(sys.argv[1]), int(sys.argv[2]), 50
def run(f, n=30):
    f(); ts=[]
    for _ in range(5):
        t=time.perf_counter()
        for _ in range(n): f()
        ts.append((time.perf_counter()-t)/n)
    ts.sort(); return ts[2]*1e3
x = torch.randn(B, I)
W0 = torch.randn(2, I, H, requires_grad=True); b0 = torch.zeros(2, 1, H, requires_grad=True)
W1 = torch.randn(2, H, H, requires_grad=True); b1 = torch.zeros(2, 1, H, requires_grad=True)
W2 = torch.randn(2, H, H, requires_grad=True); b2 = torch.zeros(2, 1, H, requires_grad=True)
W3 = torch.randn(2, H, 1, requires_grad=True); b3 = torch.zeros(2, 1, 1, requires_grad=True)
def ens():
    h = torch.baddbmm(b0, x.expand(2, B, I), W0).relu()
    h = torch.baddbmm(b1, h, W1).relu()
    h = torch.baddbmm(b2, h, W2).relu()
    q = torch.baddbmm(b3, h, W3)
    q.sum().backward()
def sep():
    outs=[]
    for e in range(2):
        h = torch.addmm(b0[e], x, W0[e]).relu()
        h = torch.addmm(b1[e], h, W1[e]).relu()
        h = torch.addmm(b2[e], h, W2[e]).relu()
        outs.append(torch.addmm(b3[e], h, W3[e]))
    torch.stack(outs).sum().backward()
for r in range(3):
    print("baddbmm %.2f ms  separate addmm %.2f ms" % (run(ens), run(sep)))
