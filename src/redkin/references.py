"""The full references of the four papers, keyed as the code cites them (``[000 eq. 21]`` is paper ``"000"``)."""

from __future__ import annotations

#: Full reference of each paper, from its seed in ``shared/seeds/`` (venue and year where the seed states them).
REFERENCES: dict[str, str] = {
    "000": (
        "M. Shimizu, H. Kakuya, W.-K. Yoon, K. Kitagaki, K. Kosuge: 関節の可動範囲を考慮に入れた7自由度冗長"
        "マニピュレータの解析的逆運動学解法 (Analytical Inverse Kinematics for 7 DOF Redundant Manipulators with "
        "Joint Limits), Journal of the Robotics Society of Japan (manuscript received 14 August 2006)."
    ),
    "001": (
        "Y. Hamada: 8自由度冗長マニピュレータの機構解析 (On Structure Analysis of 8DOF Redundant Manipulators), "
        "master's thesis, Graduate School of Engineering, Hosei University, 2005 (supervisor N. Kobayashi)."
    ),
    "003": (
        "S. Miyata, D. Sato, Y. Kanemiya (Tokyo City University): 特異点適合法に基づく擬似逆行列の性質を利用した"
        "冗長マニピュレータの逆運動学解法 (Inverse kinematics of redundant manipulators using the properties of the "
        "pseudoinverse in the singularity-consistent method), conference paper (Barrett WAM simulation)."
    ),
    "004": (
        "T. Tsuji, S. Nakayama, K. Ito: 仮想アームを用いた冗長マニピュレータの分散的軌道生成 (Distributed Trajectory "
        "Generation for Redundant Manipulators Based on Virtual Arms), Transactions of the Society of Instrument "
        "and Control Engineers (SICE) (received 17 April 1991, revised 12 August 1991)."
    ),
}
