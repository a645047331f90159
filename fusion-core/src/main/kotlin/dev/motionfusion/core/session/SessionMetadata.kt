/*
 * meta.json of a session (docs/SESSION_FORMAT.md): what was recorded, on what, when, and how.
 * Times: wall clock in ms since the Unix epoch (System.currentTimeMillis), sensor time in ns on
 * the SystemClock.elapsedRealtimeNanos base (the base of SensorEvent.timestamp).
 */
package dev.motionfusion.core.session

import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterSettings

/** The device the session was recorded on (android.os.Build). */
public data class DeviceInfo(
    val manufacturer: String = "",
    val model: String = "",
    /** Build.VERSION.RELEASE, e.g. "14". */
    val androidVersion: String = "",
    /** Build.VERSION.SDK_INT, e.g. 34; 0 when unknown. */
    val sdkInt: Int = 0,
)

/**
 * A wall-clock anchor: [wallClockMs] (System.currentTimeMillis) and [elapsedRealtimeNs]
 * (SystemClock.elapsedRealtimeNanos) read together. UTC of a sensor timestamp t:
 * wallClockMs + (t − elapsedRealtimeNs) / 1e6.
 */
public data class ClockAnchor(val wallClockMs: Long, val elapsedRealtimeNs: Long) {
    /** Unix time in ms of the sensor timestamp [timestampNs]. */
    public fun toWallClockMs(timestampNs: Long): Double {
        val d = timestampNs - elapsedRealtimeNs
        // Timestamps of opposite signs far apart overflow a Long difference: take it in doubles then.
        val overflow = ((timestampNs xor elapsedRealtimeNs) and (timestampNs xor d)) < 0
        return wallClockMs + (if (overflow) timestampNs.toDouble() - elapsedRealtimeNs.toDouble() else d.toDouble()) / 1e6
    }
}

/**
 * One sensor as android.hardware.Sensor describes it, and how it was registered. Delays in µs,
 * range and resolution in the stream's unit, power in mA.
 */
public data class SensorInfo(
    val stream: SessionStream,
    val name: String = "",
    val vendor: String = "",
    val version: Int = 0,
    /** Sensor.getType(). */
    val type: Int = stream.androidType,
    /** Sensor.getStringType(), e.g. "android.sensor.accelerometer". */
    val stringType: String = "",
    val maximumRange: Double = Double.NaN,
    val resolution: Double = Double.NaN,
    val powerMa: Double = Double.NaN,
    /** Sensor.getMinDelay(): shortest period, µs (0 for on-change sensors). */
    val minDelayUs: Int = 0,
    /** Sensor.getMaxDelay(): longest period, µs. */
    val maxDelayUs: Int = 0,
    val fifoReservedEventCount: Int = 0,
    val fifoMaxEventCount: Int = 0,
    val wakeUp: Boolean = false,
    /** The samplingPeriodUs passed to registerListener. */
    val requestedPeriodUs: Int = 0,
    /** The maxReportLatencyUs passed to registerListener (0: no batching). */
    val maxReportLatencyUs: Int = 0,
) {
    /** Requested rate, Hz (NaN for 0 = fastest). */
    public val requestedRateHz: Double get() = if (requestedPeriodUs > 0) 1e6 / requestedPeriodUs else Double.NaN
}

/**
 * The calibration stored on the phone when the session was recorded (meta.json's
 * `calibration`, docs/CALIBRATION.md). The recorded streams stay raw either way; when
 * [appliedInLiveFilter], the live filter that wrote orientation.csv ran on the corrected
 * readings, and `fusion replay` applies [calibration] by default to reproduce it.
 */
public data class SessionCalibration(val calibration: Calibration, val appliedInLiveFilter: Boolean)

/**
 * A session that continues an earlier one of the same recording, after the recording's process was
 * killed and the system restarted it: [previousSession] is the earlier session's folder name; no
 * sample was recorded from [gapStartElapsedRealtimeNs] (the earlier session's last sample, null
 * when it had none) to [gapEndElapsedRealtimeNs] (when recording resumed), both on the sensor clock.
 */
public data class Continuation(val previousSession: String, val gapStartElapsedRealtimeNs: Long?, val gapEndElapsedRealtimeNs: Long) {
    /** The gap's length, ns; null when the earlier session had no sample. */
    public val gapNs: Long? get() = gapStartElapsedRealtimeNs?.let { gapEndElapsedRealtimeNs - it }
}

/**
 * A recording started by a laptop over the live link (docs/STREAMING.md, "Remote control"): [by] the client's name
 * ("fusion record on lab-laptop"), [laptopClock] the laptop clock of its command (as [SessionMetadata.clockLink] names
 * one; null when it named none), [laptopNs] the start on that clock, [elapsedRealtimeNs] the same instant on the phone's
 * sensor clock as the laptop's clock exchanges put it (no sample of the session comes before it).
 */
public data class RemoteStart(val by: String, val laptopClock: String?, val laptopNs: Long, val elapsedRealtimeNs: Long)

/**
 * The partial wake lock of a recording (docs/RECORDING.md, "Wake lock"): [held] for the whole recording, or let go
 * once it ran because every sensor registered batches in hardware and wakes the phone itself. [reason] names the
 * case: `hardware_batching` (not held), `not_wake_up` (a sensor without a wake-up variant that batches),
 * `fifo_too_small` (the FIFOs hold too little to batch); newer versions may add others. [forcedBy]: the streams
 * whose sensors forced the lock (empty when not held).
 */
public data class WakeLockUse(val held: Boolean, val reason: String, val forcedBy: List<SessionStream> = emptyList())

/** A pause of the recording from [startElapsedRealtimeNs] to [endElapsedRealtimeNs] (null while paused). */
public data class Pause(val startElapsedRealtimeNs: Long, val endElapsedRealtimeNs: Long?)

/**
 * What was actually recorded in one stream: counts, first and last timestamps and the achieved
 * rate. Intervals longer than one second (pauses, gaps) are left out of the rate and jitter.
 *
 * @property achievedRateHz 1 / mean sample interval.
 * @property intervalStdMs standard deviation of the sample interval (jitter), ms.
 * @property backwards samples whose timestamp is earlier than the previous one's.
 * @property duplicates samples with the previous sample's timestamp.
 */
public data class StreamStats(
    val samples: Long,
    val firstTimestampNs: Long,
    val lastTimestampNs: Long,
    val achievedRateHz: Double,
    val intervalStdMs: Double,
    val backwards: Long,
    val duplicates: Long,
)

/**
 * The contents of meta.json. [formatVersion] is the version of docs/SESSION_FORMAT.md the
 * session follows; readers reject a newer major version.
 *
 * @property startAnchor wall clock and sensor clock read together when recording started.
 * @property clockLink the laptop clock of the session's clock exchanges (clock.csv), when it was linked to one.
 * @property anchors later anchors (e.g. every minute), to detect wall-clock adjustments.
 * @property sensors every sensor recorded, with its registration.
 * @property filterSettings the settings of the live filter that wrote orientation.csv, if any.
 * @property pauses pauses of the recording (samples are absent during them).
 * @property complete true once the writer closed the session normally.
 * @property recovered true when the session was repaired after its process was killed.
 * @property endElapsedRealtimeNs when recording stopped (sensor clock), null if unknown.
 * @property endReason why recording stopped: "stopped" (by the user), or a failure such as
 *   "queue_overflow", "storage_low", "write_failed: <message>"; empty when unknown.
 * @property streams per-stream counts and achieved rates, filled on close or recovery.
 * @property markers the count and first/last timestamps of markers.csv ([SessionMarkers]),
 *   listed in meta.json's `streams` as "markers"; null when the session has no markers.
 * @property source who made the session, e.g. "Motion Fusion 0.1.0" or "fusion simulate --seed 1".
 * @property calibration the phone's stored calibration at the start, and whether the live filter used it; null: none stored.
 * @property stillRecording true for the app's still recording (the phone left untouched, for `fusion allan`).
 * @property continues the earlier session this one continues after a killed recording resumed; null: none.
 * @property wakeLock whether the recording held the CPU with a wake lock, and why; null: not said (older sessions, the stream).
 */
public data class SessionMetadata(
    val formatVersion: Int = FORMAT_VERSION,
    val appVersion: String = "",
    val source: String = "",
    val device: DeviceInfo = DeviceInfo(),
    val startAnchor: ClockAnchor? = null,
    val anchors: List<ClockAnchor> = emptyList(),
    val sensors: List<SensorInfo> = emptyList(),
    val filterSettings: FilterSettings? = null,
    val pauses: List<Pause> = emptyList(),
    val complete: Boolean = false,
    val recovered: Boolean = false,
    val endElapsedRealtimeNs: Long? = null,
    val endReason: String = "",
    val streams: Map<SessionStream, StreamStats> = emptyMap(),
    val markers: StreamStats? = null,
    val calibration: SessionCalibration? = null,
    val stillRecording: Boolean = false,
    val continues: Continuation? = null,
    /** The laptop clock the exchanges of clock.csv ([SessionClock]) are on (its host and boot), null without a link. */
    val clockLink: String? = null,
    /** The laptop's command that started this recording, null when it was started on the phone. */
    val remoteStart: RemoteStart? = null,
    val wakeLock: WakeLockUse? = null,
) {
    public companion object {
        /** The version of the format this library writes (and the newest it reads). */
        public const val FORMAT_VERSION: Int = 1

        /** File name of the metadata inside a session folder. */
        public const val FILE_NAME: String = "meta.json"
    }
}
