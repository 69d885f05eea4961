//! (being written for issue 48: the plots drawn with egui_plot)
