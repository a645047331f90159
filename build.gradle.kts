// Root of the Android Studio project; see settings.gradle.kts. Plugin versions: gradle/libs.versions.toml.
plugins {
    alias(libs.plugins.android.application) apply false
    alias(libs.plugins.kotlin.android) apply false
    alias(libs.plugins.kotlin.jvm) apply false
}

allprojects {
    group = "dev.motionfusion"
    version = "0.1.0"
}
