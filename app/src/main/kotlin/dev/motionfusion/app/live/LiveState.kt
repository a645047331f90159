package dev.motionfusion.app.live

import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorSample

/** What the live screen shows: the latest sample of each sensor and the orientation. */
data class LiveState(
    val latest: Map<SensorKind, SensorSample> = emptyMap(),
    val missing: Set<SensorKind> = emptySet(),
    val orientation: OrientationReading = OrientationReading.Waiting,
)

/** Folds samples into a [LiveState]; pure logic, testable on the JVM. */
class LiveModel(missing: Set<SensorKind>) {
    private val orientation = AccMagOrientation()
    private val latest = HashMap<SensorKind, SensorSample>()
    private val missing = missing.toSet()

    fun onSample(s: SensorSample) {
        latest[s.kind] = s
        orientation.update(s)
    }

    fun state(): LiveState = LiveState(HashMap(latest), missing, orientation.current())
}
