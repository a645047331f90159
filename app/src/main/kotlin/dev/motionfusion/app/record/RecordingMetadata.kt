package dev.motionfusion.app.record

import android.hardware.Sensor
import android.os.Build
import android.os.SystemClock
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.DeviceInfo
import dev.motionfusion.core.session.SensorInfo
import dev.motionfusion.core.session.SessionCalibration
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.WakeLockUse
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.app.sensor.SamplingRate

/** The metadata of a session about to be recorded (docs/SESSION_FORMAT.md, meta.json). */
internal object RecordingMetadata {
    /** A wall-clock anchor: the midpoint of two elapsed-realtime reads around the wall-clock read. */
    fun anchorNow(): ClockAnchor {
        val e0 = SystemClock.elapsedRealtimeNanos()
        val wall = System.currentTimeMillis()
        val e1 = SystemClock.elapsedRealtimeNanos()
        return ClockAnchor(wall, e0 + (e1 - e0) / 2)
    }

    fun sensorInfo(stream: SessionStream, s: Sensor, requestedPeriodUs: Int, maxReportLatencyUs: Int) = SensorInfo(
        stream = stream,
        name = s.name ?: "",
        vendor = s.vendor ?: "",
        version = s.version,
        type = s.type,
        maximumRange = s.maximumRange.toDouble(),
        resolution = s.resolution.toDouble(),
        powerMa = s.power.toDouble(),
        minDelayUs = s.minDelay,
        maxDelayUs = s.maxDelay,
        fifoReservedEventCount = s.fifoReservedEventCount,
        fifoMaxEventCount = s.fifoMaxEventCount,
        wakeUp = s.isWakeUpSensor,
        requestedPeriodUs = requestedPeriodUs,
        maxReportLatencyUs = maxReportLatencyUs,
    )

    /**
     * The one place the app builds a session's metadata: a recording's meta.json (RecordingService)
     * and the live stream's hello (AppGraph), of [sensors] requested at [rate] with [maxReportLatencyUs];
     * [wakeLock]: whether the recording holds the CPU, and why (null: not said, the stream keeps its own).
     */
    fun create(
        appVersion: String, sensors: Map<SessionStream, Sensor>, rate: SamplingRate, maxReportLatencyUs: Int,
        settings: FilterSettings, anchor: ClockAnchor, calibration: SessionCalibration? = null, still: Boolean = false,
        wakeLock: WakeLockUse? = null,
    ) = SessionMetadata(
        appVersion = appVersion,
        source = "Motion Fusion $appVersion",
        device = DeviceInfo(Build.MANUFACTURER ?: "", Build.MODEL ?: "", Build.VERSION.RELEASE ?: "", Build.VERSION.SDK_INT),
        startAnchor = anchor,
        sensors = sensors.map { (stream, s) -> sensorInfo(stream, s, rate.nominalPeriodUs, maxReportLatencyUs) },
        filterSettings = settings,
        calibration = calibration,
        stillRecording = still,
        wakeLock = wakeLock,
    )
}
