from typing import Any, Dict, Optional, Union

Quantity = Union[float, str]

def single_disc(r1: Quantity, r2: Quantity, *, tau_y: Optional[Quantity] = ..., b: Optional[Quantity] = ...,
                fluid: str = ..., speed: Optional[Quantity] = ..., eta: Optional[Quantity] = ...,
                gap: Optional[Quantity] = ...) -> Dict[str, Any]: ...
def multi_disc(discs: int, r1: Quantity, r2: Quantity, *, tau_y: Optional[Quantity] = ...,
               b: Optional[Quantity] = ..., fluid: str = ..., speed: Optional[Quantity] = ...,
               eta: Optional[Quantity] = ..., gap: Optional[Quantity] = ...) -> Dict[str, Any]: ...
def drum(r: Quantity, h: Quantity, *, tau_y: Optional[Quantity] = ..., b: Optional[Quantity] = ...,
         fluid: str = ..., speed: Optional[Quantity] = ..., eta: Optional[Quantity] = ...,
         gap: Optional[Quantity] = ...) -> Dict[str, Any]: ...
def multi_drum(r0: Quantity, h: Quantity, d: Quantity, g: Quantity, surfaces: int, *,
               tau_y: Optional[Quantity] = ..., b: Optional[Quantity] = ..., fluid: str = ...,
               speed: Optional[Quantity] = ..., eta: Optional[Quantity] = ...) -> Dict[str, Any]: ...
def coil(window_width: Quantity, window_height: Quantity, *, awg: Optional[int] = ...,
         wire_diameter: Optional[Quantity] = ..., inner_radius: Quantity = ..., turns: Optional[int] = ...,
         current: Quantity = ..., temperature: Quantity = ...) -> Dict[str, Any]: ...
