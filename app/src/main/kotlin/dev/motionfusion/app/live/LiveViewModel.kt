package dev.motionfusion.app.live

import androidx.lifecycle.ViewModel
import androidx.lifecycle.ViewModelProvider
import dev.motionfusion.app.sensor.SensorInfo
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.ui.AngleTrace
import kotlinx.coroutines.flow.StateFlow
import dev.motionfusion.app.fusion.Capture
import dev.motionfusion.app.fusion.FusionState

/**
 * The live screen's state: the application's [Capture], which survives configuration changes
 * (it belongs to the application, not to the activity), held while the screen is visible, and the
 * plot's last 10 s ([plotTrace]), which a new activity after a rotation draws on.
 */
class LiveViewModel(private val capture: Capture) : ViewModel() {
    /** The latest fusion result, published by the capture thread. */
    val state: StateFlow<FusionState> get() = capture.state

    /** Name, vendor and limits of each sensor the device has. */
    val sensorInfo: Map<SensorKind, SensorInfo> get() = capture.sensorInfo

    /** The live plot's history, kept across configuration changes (main thread only). */
    val plotTrace = AngleTrace()

    private var visible = false

    /** The screen became visible: the capture runs (a recording may hold it too). */
    fun onVisible() {
        if (visible) return
        visible = true
        capture.acquire(onScreen = true)
    }

    /** The screen was hidden. */
    fun onHidden() {
        if (!visible) return
        visible = false
        capture.release(onScreen = true)
    }

    override fun onCleared() = onHidden()

    class Factory(private val capture: Capture) : ViewModelProvider.Factory {
        @Suppress("UNCHECKED_CAST")
        override fun <T : ViewModel> create(modelClass: Class<T>): T {
            require(modelClass.isAssignableFrom(LiveViewModel::class.java)) { "unknown ViewModel $modelClass" }
            return LiveViewModel(capture) as T
        }
    }
}
